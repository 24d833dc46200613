// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A fixed-free spring-mass chain as an FE tool would export it (tests of issue 58): its Matrix
// Market files, row map and node table, and its analytic frequencies,
// w_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N + 1))).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "numeric/constants.hpp"

namespace flexloop::test {

inline std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("flexloop_test_superelement_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

// A chain of n masses m on n springs k, the first spring to the ground: K and M as Matrix
// Market files, K symmetric (lower triangle), M general (its diagonal).
inline void write_chain(const std::filesystem::path& dir, int n, double k, double m) {
  std::ofstream kf(dir / "K.mtx"), mf(dir / "M.mtx");
  kf << "%%MatrixMarket matrix coordinate real symmetric\n% a chain\n"
     << n << " " << n << " " << 2 * n - 1 << "\n";
  for (int i = 1; i <= n; ++i) {
    char line[96];
    std::snprintf(line, sizeof line, "%d %d %.17g\n", i, i, i < n ? 2 * k : k);
    kf << line;
    if (i < n) {
      std::snprintf(line, sizeof line, "%d %d %.17g\n", i + 1, i, -k);
      kf << line;
    }
  }
  mf << "%%MatrixMarket matrix coordinate real general\n" << n << " " << n << " " << n << "\n";
  for (int i = 1; i <= n; ++i) mf << i << " " << i << " " << m << "\n";
}

inline double chain_hz(int n, double k, double m, int j) {
  return 2 * std::sqrt(k / m) * std::sin((2 * j - 1) * numeric::kPi / (2 * (2 * n + 1))) /
         numeric::kTwoPi;
}

// The chain's row map (mesh node i, direction 1 = x) and node table (node i at x = 0.01 i), as
// CSV files dofs.csv and nodes.csv.
inline void write_chain_maps(const std::filesystem::path& dir, int n) {
  std::ofstream df(dir / "dofs.csv"), nf(dir / "nodes.csv");
  df << "node,direction\n";
  nf << "id,x,y,z\n";
  for (int i = 1; i <= n; ++i) {
    df << i << ",1\n";
    nf << i << "," << 0.01 * i << ",0,0\n";
  }
}

}  // namespace flexloop::test
