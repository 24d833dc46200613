// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What a Craig-Bampton reduction leaves out, in a form that costs nothing per frequency (issue 58
// item 3: the reduction's error measured, not assumed). With the body's dynamic stiffness
// Z = a K - b M (a = 1, b = w^2 undamped; a = 1 + i w beta, b = w^2 - i w alpha with Rayleigh
// damping alpha M + beta K), its interface dynamic stiffness, the interior condensed exactly, is
//   S_full(w) = a Khat - b Mhat - b^2 R' Z_ii^-1 R,     R = M_ib + M_ii Psi,
// (Khat, Mhat: the reduced interface block; Psi the constraint modes), and the reduced body's is
// the same with Z_ii^-1 replaced by its kept modes' part Phi (a W^2 - b I)^-1 Phi'. The
// difference is the unkept fixed-interface modes' part, a series in b / a that converges below
// the first unkept mode w_{m+1} (>= w_c, the cut-off: every mode below it is kept):
//   S_full - S_red = -(b^2 / a) sum_j z^j nu_j,   z = b / (a w_c^2),
//   nu_j = w_c^(2j) mu_j,   mu_j = R' G (M_ii G)^j R = sum_{k unkept} n_k n_k' / w_k^(2j+2),
// G = Pi K_ii^-1, Pi = I - Phi Phi' M_ii (the unkept modes' part), n_k = phi_k' R. Each nu_j is
// symmetric positive semi-definite and nu_j <= nu_0 (w_k >= w_c), so the terms past J are bounded
// by ||nu_0|| |z|^J / (1 - |z|): the series is exact to a stated bound, with no factorisation
// per frequency.
//
// Cost, at reduction time, on the reduction's own factor of K_ii: c_0 = G R, c_{k+1} = w_c^2 G
// M_ii c_k (k < J), each one solve with n_b right-hand sides and a projection against Phi; then
// nu_0 = R' c_0, nu_{2k+1} = c_k' M_ii c_k, nu_{2k+2} = c_k' M_ii c_{k+1}: 2 J + 2 moments for
// J + 1 block solves. Memory: three n_i x n_b blocks.
#include <Eigen/Dense>
#include <functional>
#include <vector>

#include "plant/superelement/sparse_text.hpp"

namespace flexloop::plant::superelement {

struct ResidualMoments {
  std::vector<Eigen::MatrixXd> scaled;  ///< nu_j = w_c^(2j) mu_j, n_b x n_b each
  double cut_off_rad2 = 0;              ///< w_c^2 (rad^2/s^2)
};

/// y = K_ii^-1 x (the reduction's factor).
using InteriorSolve = std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>;

/// The moments above from K_ii's solve, M_ii, the kept modes (Phi M_ii-normalised, their w^2 in
/// `lambda`) and R = M_ib + M_ii Psi; `block_solves` = J + 1 (at least 1).
ResidualMoments residual_moments(const InteriorSolve& solve, const SparseMatrix& mii,
                                 const Eigen::MatrixXd& phi, const Eigen::VectorXd& lambda,
                                 const Eigen::MatrixXd& r, double cut_off_rad2, int block_solves);

/// The block solves for a series exact to `tolerance` of its first term up to `band_hz` (at most
/// half the cut-off; undamped, |z| = (f / f_c)^2): the fewest J with |z|^(2J) / (1 - |z|) <=
/// tolerance. 0 for a band <= 0.
int residual_block_solves(double band_hz, double cut_off_hz, double tolerance = 1e-4);

}  // namespace flexloop::plant::superelement
