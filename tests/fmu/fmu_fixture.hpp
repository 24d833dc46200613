// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The fixture FMUs the build zips (tools/fmu) as the tests use them: their paths, the settings
// that run them as a given PI or state-space controller, and archives made from the PI fixture's
// parts (bad fixtures).
#include <zip.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "artefact/pi_parameters.hpp"
#include "artefact/state_space_parameters.hpp"
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
/// The state-space fixture sized for the shipped LQG (12 states, 6 sensors, 6 actuators) and one
/// of 1 state, 1 sensor, 1 actuator (tools/fmu/state_space_controller).
inline std::string state_space_fmu_path() {
  return FLEXLOOP_STATE_SPACE_FMU;
}
inline std::string state_space_1x1x1_fmu_path() {
  return FLEXLOOP_STATE_SPACE_1X1X1_FMU;
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

/// Settings running a state-space fixture as `p`: A, B, C, D, D22 (zero when `p` has none), the
/// limits per channel, anti_windup (0 none, 1 hold) and feedthrough_delay as parameters, inputs
/// y1.., outputs u1...
inline controller::fmu::FmuControllerSettings state_space_fmu_settings(
    const artefact::StateSpaceParameters& p, const std::string& file) {
  const Eigen::Index ns = p.B.cols(), nc = p.C.rows();
  controller::fmu::FmuControllerSettings s;
  s.file = file;
  s.period = p.dt;
  for (Eigen::Index i = 0; i < ns; ++i) s.inputs.push_back("y" + std::to_string(i + 1));
  for (Eigen::Index i = 0; i < nc; ++i) s.outputs.push_back("u" + std::to_string(i + 1));
  const auto matrix = [&](const std::string& name, const Eigen::MatrixXd& m) {
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j)
        s.parameters.emplace_back(name + "_" + std::to_string(i + 1) + "_" + std::to_string(j + 1),
                                  m(i, j));
  };
  matrix("A", p.A);
  matrix("B", p.B);
  matrix("C", p.C);
  matrix("D", p.D);
  matrix("D22", p.feedthrough.size() > 0 ? p.feedthrough : Eigen::MatrixXd::Zero(ns, nc));
  for (const auto& [name, limit] : {std::pair{"u_min_", &p.u_min}, std::pair{"u_max_", &p.u_max}})
    if (limit->size() > 0)  // one value for every channel, or one per channel
      for (Eigen::Index i = 0; i < nc; ++i)
        s.parameters.emplace_back(name + std::to_string(i + 1),
                                  (*limit)(limit->size() == 1 ? 0 : i));
  s.parameters.emplace_back("anti_windup", p.anti_windup == artefact::AntiWindup::kHold ? 1 : 0);
  s.parameters.emplace_back("feedthrough_delay", p.feedthrough_delay);
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
