#include "controller/fmu/fmu_library.hpp"

#include <dlfcn.h>

#include "common/input_error.hpp"

namespace flexloop::controller::fmu {

namespace {

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

}  // namespace

FmuLibrary::FmuLibrary(const std::filesystem::path& dir, const std::string& model_identifier,
                       const std::string& fmu) {
  const auto so = dir / "binaries" / "linux64" / (model_identifier + ".so");
  if (!std::filesystem::is_regular_file(so))
    throw common::InputError(fmu,
                             "no binaries/linux64/" + model_identifier +
                                 ".so in the archive (flexloop runs the FMU's linux64 binary)");
  // RTLD_LOCAL: two FMUs may export the same fmi2 names. RTLD_NOW: a missing symbol is an error
  // here, at start-up, not in the loop.
  handle_ = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle_) {
    const char* why = dlerror();
    throw common::InputError(fmu, "cannot load binaries/linux64/" + model_identifier +
                                      ".so: " + (why ? why : "dlopen failed"));
  }
  try {
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
