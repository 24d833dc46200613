#pragma once
// An FMU's archive unpacked into a private temporary directory (mkdtemp: mode 0700, a name no
// one else holds), removed with everything in it when the object goes. Start-up only.
#include <filesystem>
#include <string>

namespace flexloop::controller::fmu {

class FmuDirectory {
 public:
  /// @throws flexloop::InputError naming `fmu` when it cannot be read, is not a zip archive, or
  /// an entry cannot be extracted (or would land outside the directory).
  explicit FmuDirectory(const std::string& fmu);
  ~FmuDirectory();
  FmuDirectory(const FmuDirectory&) = delete;
  FmuDirectory& operator=(const FmuDirectory&) = delete;

  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace flexloop::controller::fmu
