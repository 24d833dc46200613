// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The stationary covariance of a discrete linear system driven by white noise,
//   x_{k+1} = A x_k + B n_k,  E[n nᵀ] = I:   P = A P Aᵀ + B Bᵀ,
// by the doubling (Smith) iteration P <- P + A P Aᵀ, A <- A²: after j rounds P holds
// Σ_{i < 2^j} A^i B Bᵀ A^iᵀ. It converges when every mode the noise reaches is inside the unit
// circle; a mode on the circle that the noise does not reach (an integrator whose input is the
// difference of a stationary signal) leaves only rounding behind, which doubles each round from
// 1e-32 and stays far below the stopping test for the 64 rounds allowed. A mode the noise drives
// on or outside the circle makes the sum grow: no stationary state.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace flexloop::numeric {

/// P, or nothing when the sum does not settle in 64 rounds (a driven mode on or outside the unit
/// circle) or overflows. Cost: three n x n products a round; a mode at radius 1 - e needs about
/// log2(37 / e) rounds (e = 1e-7: 29).
inline std::optional<Eigen::MatrixXd> stationary_covariance(const Eigen::MatrixXd& A,
                                                            const Eigen::MatrixXd& B) {
  Eigen::MatrixXd p = B * B.transpose(), a = A;
  for (int round = 0; round < 64; ++round) {
    const Eigen::MatrixXd increment = a * p * a.transpose();
    p += increment;
    if (!p.allFinite()) return std::nullopt;
    // Max-norm: the Frobenius norm of a diverging sum overflows to inf <= inf.
    if (increment.cwiseAbs().maxCoeff() <= 1e-16 * p.cwiseAbs().maxCoeff()) return p;
    a = (a * a).eval();
  }
  return std::nullopt;
}

/// R with R Rᵀ = P for a covariance P that is only semidefinite (a Cholesky factor may not
/// exist): R = V sqrt(max(Λ, 0)) of P = V Λ Vᵀ. A draw R z, z standard normal, has covariance P.
inline Eigen::MatrixXd covariance_root(const Eigen::MatrixXd& P) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(P);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal();
}

/// What keeps P from being a covariance, or empty: an entry that is not symmetric, or an
/// eigenvalue below zero by more than rounding (1e-9 of the largest). For matrices read from a
/// file (an artefact's start), where a hand edit may have broken either.
inline std::string covariance_defect(const Eigen::MatrixXd& P) {
  if (P.size() == 0) return {};
  std::ostringstream os;
  os.precision(3);
  const double scale = P.cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < P.cols(); ++j)
    for (Eigen::Index i = j + 1; i < P.rows(); ++i)
      if (!(std::abs(P(i, j) - P(j, i)) <= 1e-12 * scale)) {
        os << "not symmetric: entry (" << i << ", " << j << ") is " << P(i, j) << ", entry (" << j
           << ", " << i << ") " << P(j, i);
        return os.str();
      }
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P).eigenvalues();
  const double largest = lambda(lambda.size() - 1);
  if (lambda(0) >= -1e-9 * std::max(largest, 0.0)) return {};
  os << "not positive semidefinite: eigenvalue " << lambda(0) << " against the largest " << largest;
  return os.str();
}

}  // namespace flexloop::numeric
