// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// CalculiX in the superelement tests (issue 58): running ccx (a project dependency, installed
// by tools/lib/common.sh), and reading its eigenvalue table and printed displacements from
// jobname.dat.
#include <catch2/catch.hpp>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace flexloop::test {

/// A folder removed when the test process ends, even when a step that fills it fails.
struct RemovedAtExit {
  std::filesystem::path dir;
  ~RemovedAtExit() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

inline void run(const std::string& command) {
  INFO(command);
  REQUIRE(std::system(command.c_str()) == 0);
}

inline void require_calculix() {
  if (std::system("command -v ccx > /dev/null") != 0)
    FAIL(
        "ccx not found: CalculiX (calculix-ccx) is a project dependency, installed by "
        "tools/lib/common.sh");
}

/// The eigenvalues (w^2) of jobname.dat's "E I G E N V A L U E   O U T P U T" table, in mode
/// order: its rows are "mode eigenvalue rad/time cycles/time imaginary"; the eigenvalue column
/// has 7 significant digits, the cycles column fewer of the frequency, so it is the one read.
inline std::vector<double> calculix_eigenvalues(const std::filesystem::path& dat) {
  std::ifstream in(dat);
  std::string line;
  while (std::getline(in, line) && line.find("E I G E N V A L U E   O U T P U T") == line.npos) {
  }
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    long mode = 0;
    double lambda = 0;
    if (fields >> mode >> lambda) {
      if (mode != static_cast<long>(out.size()) + 1) break;
      out.push_back(lambda);
    } else if (!out.empty()) {
      break;  // the blank line after the table
    }
  }
  return out;
}

/// A node's (vx, vy, vz) from jobname.dat's "displacements (vx,vy,vz) for set ..." table (a
/// *NODE PRINT of U; 7 significant digits). A missing node fails the test.
inline std::array<double, 3> calculix_displacement(const std::filesystem::path& dat, long node) {
  std::ifstream in(dat);
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.find("displacements (vx,vy,vz)") != line.npos) {
      inside = true;
      continue;
    }
    std::istringstream fields(line);
    long id = 0;
    std::array<double, 3> u{};
    if (inside && fields >> id >> u[0] >> u[1] >> u[2] && id == node) return u;
  }
  FAIL("no displacement of node " << node << " in " << dat);
  return {};
}

}  // namespace flexloop::test
