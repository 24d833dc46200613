// SPDX-License-Identifier: BSD-3-Clause
#include "plant/runtime/pole_precision.hpp"

#include <Eigen/Eigenvalues>
#include <complex>
#include <limits>

namespace flexloop::plant::runtime {

void require_dense_poles_kept_inside(const Eigen::MatrixXd& Ad, const Eigen::MatrixXd& stored,
                                     const std::string& who) {
  if (Ad.rows() == 0) return;
  const Eigen::VectorXcd exact = Eigen::EigenSolver<Eigen::MatrixXd>(Ad, false).eigenvalues();
  const Eigen::VectorXcd kept = Eigen::EigenSolver<Eigen::MatrixXd>(stored, false).eigenvalues();
  // An eigenvalue of a dense matrix is computed to about eps |Ad|: within that of the circle, a
  // pole is on it (marginal in double already).
  const double resolution = 64 * std::numeric_limits<double>::epsilon() * Ad.lpNorm<1>();
  for (Eigen::Index i = 0; i < exact.size(); ++i) {
    const std::complex<double> z = exact(i);
    const double a = z.real() - 1, b = z.imag(), margin = std::norm(z) - 1;
    if (!(margin < 0) || on_unit_circle(a, b, margin) || -margin <= resolution) continue;
    Eigen::Index nearest = 0;
    (kept.array() - z).abs().minCoeff(&nearest);
    const double stored_margin = std::norm(kept(nearest)) - 1;
    // The pairing's own rounding, as above, is not a change of the decay.
    const double change = std::abs(stored_margin - margin);
    if (stored_margin < 0 && (change <= resolution || change <= kDecayTolerance * -margin))
      continue;
    throw_pole_not_kept(who, "a pole of Ad", a, b, margin, stored_margin,
                        "with Ad - I stored in float");
  }
}

}  // namespace flexloop::plant::runtime
