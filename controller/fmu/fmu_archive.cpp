#include "controller/fmu/fmu_archive.hpp"

#include <zip.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <system_error>
#include <vector>

#include "common/input_error.hpp"

namespace flexloop::controller::fmu {

namespace {

namespace fs = std::filesystem;

// An entry's name as a path inside the directory; empty for a name that would leave it.
fs::path inside(const fs::path& dir, const std::string& name) {
  const fs::path rel = fs::path(name).lexically_normal();
  if (rel.empty() || rel.is_absolute() || *rel.begin() == "..") return {};
  return dir / rel;
}

void extract(zip_t* z, const fs::path& dir, const std::string& fmu) {
  const zip_int64_t n = zip_get_num_entries(z, 0);
  std::vector<char> buffer(1 << 16);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(z, static_cast<zip_uint64_t>(i), 0);
    if (!name) throw common::InputError(fmu, "an entry of the archive has no name");
    const fs::path target = inside(dir, name);
    if (target.empty())
      throw common::InputError(fmu, std::string("entry '") + name + "' leaves the archive");
    if (std::string(name).ends_with('/')) {
      fs::create_directories(target);
      continue;
    }
    fs::create_directories(target.parent_path());
    std::unique_ptr<zip_file_t, decltype(&zip_fclose)> in(
        zip_fopen_index(z, static_cast<zip_uint64_t>(i), 0), &zip_fclose);
    std::ofstream out(target, std::ios::binary);
    if (!in || !out) throw common::InputError(fmu, std::string("cannot extract '") + name + "'");
    for (zip_int64_t got; (got = zip_fread(in.get(), buffer.data(), buffer.size())) > 0;)
      out.write(buffer.data(), got);
    if (!out) throw common::InputError(fmu, std::string("cannot extract '") + name + "'");
  }
}

}  // namespace

FmuDirectory::FmuDirectory(const std::string& fmu) {
  int code = 0;
  zip_t* z = zip_open(fmu.c_str(), ZIP_RDONLY, &code);
  if (!z) {
    zip_error_t e;
    zip_error_init_with_code(&e, code);
    const std::string why = zip_error_strerror(&e);
    zip_error_fini(&e);
    throw common::InputError(fmu, "not an FMU: cannot open it as a zip archive (" + why + ")");
  }
  std::unique_ptr<zip_t, decltype(&zip_discard)> archive(z, &zip_discard);
  std::string pattern = (fs::temp_directory_path() / "flexloop-fmu-XXXXXX").string();
  if (!mkdtemp(pattern.data()))
    throw common::InputError(fmu, "cannot create a temporary directory to unpack it into");
  dir_ = pattern;
  try {
    extract(archive.get(), dir_, fmu);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
    throw;
  }
}

FmuDirectory::~FmuDirectory() {
  std::error_code ignored;  // nothing to do about a directory that will not go
  fs::remove_all(dir_, ignored);
}

}  // namespace flexloop::controller::fmu
