// SPDX-License-Identifier: BSD-3-Clause
#include "controller/fmu/fmu_library.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <mutex>
#include <set>
#include <system_error>

#include "common/input_error.hpp"

namespace flexloop::controller::fmu {

namespace {

namespace fs = std::filesystem;

template <class F>
void resolve(void* handle, const char* name, F*& f, const std::string& fmu) {
  dlerror();
  f = reinterpret_cast<F*>(dlsym(handle, name));
  if (!f) {
    const char* why = dlerror();
    throw common::InputError(fmu, std::string("its library does not export ") + name +
                                      (why ? std::string(" (") + why + ")" : ""));
  }
}

// The GUIDs of the once-per-process FMUs loaded now (start-up only: a lock is fine).
std::mutex claims_mutex;
std::set<std::string> claimed_guids;

FmuDescription described(const fs::path& dir, const std::string& model_identifier,
                         const std::string& fmu) {
  FmuDescription d = read_fmu_description(dir, fmu);
  if (d.model_identifier != model_identifier)
    throw common::InputError(fmu, "its modelDescription.xml names the library \"" +
                                      d.model_identifier + "\", not \"" + model_identifier + "\"");
  return d;
}

// binaries/linux64/<id>.so with its links resolved, refused before dlopen (which runs the
// library's constructors) unless it lies inside the unpacked folder: an identifier such as
// "../../x" or "/tmp/x" would name another library on the machine.
fs::path library_inside(const fs::path& dir, const std::string& id, const std::string& fmu) {
  if (!is_c_identifier(id))
    throw common::InputError(fmu, "modelIdentifier \"" + id +
                                      "\" is not a C identifier ([A-Za-z_][A-Za-z0-9_]*): no "
                                      "library is loaded for it");
  const std::string relative = "binaries/linux64/" + id + ".so";
  const fs::path so = dir / relative;
  if (!fs::is_regular_file(so))
    throw common::InputError(
        fmu, "no " + relative + " in the archive (flexloop runs the FMU's linux64 binary)");
  std::error_code folder_error, library_error;
  const fs::path folder = fs::canonical(dir, folder_error);
  const fs::path library = fs::canonical(so, library_error);
  const bool inside =
      !folder_error && !library_error &&
      std::mismatch(folder.begin(), folder.end(), library.begin(), library.end()).first ==
          folder.end();
  if (!inside)
    throw common::InputError(fmu, relative + " resolves to " + library.string() +
                                      ", outside the FMU's unpacked folder: not loaded");
  return library;
}

// FMI 2.0, 2.1.4: the importer checks both before it instantiates.
void check_platform_and_version(void* handle, const std::string& fmu) {
  fmi2GetTypesPlatformTYPE* types_platform = nullptr;
  fmi2GetVersionTYPE* version = nullptr;
  resolve(handle, "fmi2GetTypesPlatform", types_platform, fmu);
  resolve(handle, "fmi2GetVersion", version, fmu);
  const auto quoted = [](const char* s) { return s ? "\"" + std::string(s) + "\"" : "no string"; };
  const char* platform = types_platform();
  if (!platform || std::string(platform) != "default")
    throw common::InputError(fmu, "its fmi2GetTypesPlatform returns " + quoted(platform) +
                                      ", not \"default\": flexloop passes the standard's default "
                                      "types (fmi2Real double, fmi2ValueReference unsigned int)");
  const char* v = version();
  if (!v || std::string(v) != "2.0")
    throw common::InputError(fmu, "its fmi2GetVersion returns " + quoted(v) +
                                      ", not \"2.0\": flexloop calls FMI 2.0 functions");
}

}  // namespace

FmuLibrary::ProcessClaim::ProcessClaim(const FmuDescription& d, const std::string& fmu) {
  if (!d.only_once_per_process) return;
  const std::lock_guard lock(claims_mutex);
  if (!claimed_guids.insert(d.guid).second)
    throw common::InputError(fmu,
                             "canBeInstantiatedOnlyOncePerProcess=\"true\" and this process "
                             "already runs an instance of it (guid " +
                                 d.guid + "): one instance per process");
  guid = d.guid;
}

FmuLibrary::ProcessClaim::~ProcessClaim() {
  if (guid.empty()) return;
  const std::lock_guard lock(claims_mutex);
  claimed_guids.erase(guid);
}

FmuLibrary::FmuLibrary(const fs::path& dir, const std::string& model_identifier,
                       const std::string& fmu)
    : FmuLibrary(dir, described(dir, model_identifier, fmu), fmu) {}

FmuLibrary::FmuLibrary(const fs::path& dir, const FmuDescription& description,
                       const std::string& fmu)
    : claim_(description, fmu) {
  const std::string& id = description.model_identifier;
  const fs::path so = library_inside(dir, id, fmu);
  // RTLD_LOCAL: two FMUs may export the same fmi2 names. RTLD_NOW: a missing symbol is an error
  // here, at start-up, not in the loop.
  handle_ = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle_) {
    const char* why = dlerror();
    throw common::InputError(
        fmu, "cannot load binaries/linux64/" + id + ".so: " + (why ? why : "dlopen failed"));
  }
  try {
    check_platform_and_version(handle_, fmu);
    resolve(handle_, "fmi2Instantiate", calls_.instantiate, fmu);
    resolve(handle_, "fmi2FreeInstance", calls_.free_instance, fmu);
    resolve(handle_, "fmi2SetupExperiment", calls_.setup_experiment, fmu);
    resolve(handle_, "fmi2EnterInitializationMode", calls_.enter_initialization_mode, fmu);
    resolve(handle_, "fmi2ExitInitializationMode", calls_.exit_initialization_mode, fmu);
    resolve(handle_, "fmi2Terminate", calls_.terminate, fmu);
    resolve(handle_, "fmi2Reset", calls_.reset, fmu);
    resolve(handle_, "fmi2SetReal", calls_.set_real, fmu);
    resolve(handle_, "fmi2GetReal", calls_.get_real, fmu);
    resolve(handle_, "fmi2DoStep", calls_.do_step, fmu);
    calls_.get_real_status =
        reinterpret_cast<fmi2GetRealStatusTYPE*>(dlsym(handle_, "fmi2GetRealStatus"));
    calls_.get_boolean_status =
        reinterpret_cast<fmi2GetBooleanStatusTYPE*>(dlsym(handle_, "fmi2GetBooleanStatus"));
  } catch (...) {
    dlclose(handle_);
    throw;
  }
}

FmuLibrary::~FmuLibrary() {
  dlclose(handle_);
}

}  // namespace flexloop::controller::fmu
