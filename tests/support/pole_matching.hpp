// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Comparing computed poles with expected roots (tests of closed loops against polynomials).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <complex>
#include <unsupported/Eigen/Polynomials>
#include <vector>

namespace flexloop::test {

/// Roots of a real polynomial given highest power first (an independent route: no matrices of
/// ours, Eigen's companion-matrix solver).
template <std::size_t N>
std::vector<std::complex<double>> polynomial_roots(const std::array<double, N>& descending) {
  static_assert(N >= 2);
  Eigen::Matrix<double, static_cast<int>(N), 1> ascending;
  for (std::size_t i = 0; i < N; ++i)
    ascending(static_cast<Eigen::Index>(i)) = descending[N - 1 - i];
  Eigen::PolynomialSolver<double, static_cast<int>(N) - 1> solver(ascending);
  return {solver.roots().data(), solver.roots().data() + N - 1};
}

/// Every expected root is matched to its own nearest unused pole, `multiplicity` times; returns
/// the worst distance relative to scale (the poles left over are ignored).
inline double match_poles(const Eigen::VectorXcd& poles,
                          const std::vector<std::complex<double>>& roots, int multiplicity,
                          double scale) {
  double worst = 0;
  std::vector<bool> used(static_cast<std::size_t>(poles.size()), false);
  for (const auto& r : roots)
    for (int k = 0; k < multiplicity; ++k) {
      double best = 1e300;
      Eigen::Index bi = -1;
      for (Eigen::Index i = 0; i < poles.size(); ++i)
        if (!used[static_cast<std::size_t>(i)] && std::abs(poles(i) - r) < best)
          best = std::abs(poles(i) - r), bi = i;
      if (bi < 0) return 1e300;  // more roots than poles
      used[static_cast<std::size_t>(bi)] = true;
      worst = std::max(worst, best / scale);
    }
  return worst;
}

}  // namespace flexloop::test
