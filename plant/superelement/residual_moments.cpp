// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/residual_moments.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flexloop::plant::superelement {

namespace {

// Pi x = x - Phi Phi' M_ii x: the kept modes taken out (the Lanczos vectors are exact to ~1e-8,
// so each step takes out again what rounding and their error let in).
Eigen::MatrixXd without_kept_modes(const Eigen::MatrixXd& x, const SparseMatrix& mii,
                                   const Eigen::MatrixXd& phi) {
  if (phi.cols() == 0) return x;
  const Eigen::MatrixXd m_x = mii * x;
  return x - phi * (phi.transpose() * m_x);
}

Eigen::MatrixXd symmetrised(const Eigen::MatrixXd& a) {
  return 0.5 * (a + a.transpose());
}

}  // namespace

ResidualMoments residual_moments(const InteriorSolve& solve, const SparseMatrix& mii,
                                 const Eigen::MatrixXd& phi, const Eigen::VectorXd& lambda,
                                 const Eigen::MatrixXd& r, double cut_off_rad2, int block_solves) {
  if (block_solves < 1 || !(cut_off_rad2 > 0))
    throw std::invalid_argument("residual_moments: at least one solve and a cut-off above 0");
  if (phi.cols() != lambda.size() || phi.rows() != mii.rows() || r.rows() != mii.rows())
    throw std::invalid_argument("residual_moments: sizes of Phi, lambda, M_ii and R disagree");
  ResidualMoments out;
  out.cut_off_rad2 = cut_off_rad2;
  // Scaled blocks d_k = w_c^(2k+1) c_k, so that d_k' M_ii d_k = nu_{2k+1} and d_k' M_ii d_{k+1} =
  // nu_{2k+2}. d_0 = w_c (K_ii^-1 R - Phi W^-2 Phi' R): the static response without the kept
  // modes' part.
  const double w_c = std::sqrt(cut_off_rad2);
  Eigen::MatrixXd c = solve(r);
  if (phi.cols() > 0) c -= phi * (lambda.cwiseInverse().asDiagonal() * (phi.transpose() * r));
  c = w_c * without_kept_modes(c, mii, phi);
  out.scaled.push_back(symmetrised(r.transpose() * c) / w_c);
  Eigen::MatrixXd m_c = mii * c;
  for (int k = 1; k < block_solves; ++k) {
    out.scaled.push_back(symmetrised(c.transpose() * m_c));  // nu_{2k-1}
    Eigen::MatrixXd next = without_kept_modes(cut_off_rad2 * solve(m_c), mii, phi);
    out.scaled.push_back(symmetrised(m_c.transpose() * next));  // nu_{2k}
    c = std::move(next);
    m_c = mii * c;
  }
  out.scaled.push_back(symmetrised(c.transpose() * m_c));
  return out;
}

int residual_block_solves(double band_hz, double cut_off_hz, double tolerance) {
  if (!(band_hz > 0) || !(cut_off_hz > 0)) return 0;
  const double z = std::pow(std::min(band_hz / cut_off_hz, 0.5), 2);
  int solves = 1;  // 2 J moments
  while (std::pow(z, 2 * solves) / (1 - z) > tolerance) ++solves;
  return solves;
}

}  // namespace flexloop::plant::superelement
