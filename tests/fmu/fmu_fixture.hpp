#pragma once
// The fixture FMU the build zips (tools/fmu/pi_force_feedback) as the tests use it: its path, the
// settings that run it as a given PI, and archives made from its parts (bad fixtures).
#include <zip.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>

#include "artefact/pi_parameters.hpp"
#include "controller/fmu/fmu_archive.hpp"
#include "controller/fmu/fmu_controller.hpp"

namespace flexloop::test {

/// A private temporary directory (mkdtemp), removed with everything in it at the end of scope.
struct TemporaryDirectory {
  std::filesystem::path path;
  TemporaryDirectory() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "flexloop-test-fmu-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp: " + pattern);
    path = pattern;
  }
  ~TemporaryDirectory() { std::filesystem::remove_all(path); }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
};

inline std::string pi_fmu_path() {
  return FLEXLOOP_PI_FMU;
}

/// Settings running the fixture as the PI `p` (6 channels, D22 = I, no delay): its gains, leak
/// and (one value each) limits as parameters, inputs y1..y6, outputs u1..u6.
inline controller::fmu::FmuControllerSettings pi_fmu_settings(const artefact::PiParameters& p,
                                                              const std::string& file) {
  controller::fmu::FmuControllerSettings s;
  s.file = file;
  s.period = p.dt;
  for (int i = 0; i < 6; ++i) {
    s.inputs.push_back("y" + std::to_string(i + 1));
    s.outputs.push_back("u" + std::to_string(i + 1));
    for (int j = 0; j < 6; ++j) {
      const std::string ij = "_" + std::to_string(i + 1) + "_" + std::to_string(j + 1);
      s.parameters.emplace_back("K_P" + ij, p.K_P(i, j));
      s.parameters.emplace_back("K_I" + ij, p.K_I(i, j));
    }
  }
  s.parameters.emplace_back("leak_rad_s", p.leak_rad_s);
  if (p.u_min.size() > 0) s.parameters.emplace_back("u_min", p.u_min(0));
  if (p.u_max.size() > 0) s.parameters.emplace_back("u_max", p.u_max(0));
  return s;
}

inline std::string read_bytes(const std::filesystem::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The fixture's entries: name -> bytes.
inline std::map<std::string, std::string> pi_fmu_entries() {
  const controller::fmu::FmuDirectory d(pi_fmu_path());
  return {{"modelDescription.xml", read_bytes(d.path() / "modelDescription.xml")},
          {"binaries/linux64/pi_force_feedback.so",
           read_bytes(d.path() / "binaries/linux64/pi_force_feedback.so")}};
}

/// Writes a zip archive of `entries` to `path`.
inline void write_zip(const std::filesystem::path& path,
                      const std::map<std::string, std::string>& entries) {
  int code = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
  if (!z) throw std::runtime_error("write_zip: cannot create " + path.string());
  for (const auto& [name, bytes] : entries) {
    zip_source_t* src = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
    if (!src || zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE) < 0) {
      zip_source_free(src);
      zip_discard(z);
      throw std::runtime_error("write_zip: cannot add " + name);
    }
  }
  if (zip_close(z) != 0) throw std::runtime_error("write_zip: cannot write " + path.string());
}

}  // namespace flexloop::test
