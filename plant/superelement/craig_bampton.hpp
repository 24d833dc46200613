// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Craig-Bampton reduction of a linear FE body given by its sparse stiffness K and mass M
// (issue 58): the interface DOFs kept as they are, the interior represented by the static
// constraint modes Psi = -K_ii^-1 K_ib (one sparse Cholesky of K_ii, CHOLMOD) and the
// fixed-interface normal modes Phi of (K_ii, M_ii) below a cut-off (shift-invert Lanczos on the
// sparse pencil, Spectra, about sigma = 0 with the same factor of K_ii; later batches of modes
// on the operator with the earlier ones deflated). With T = [I 0; Psi Phi]:
//   K_r = [K_bb + K_bi Psi, 0; 0, diag(w_k^2)],
//   M_r = [M_bb + M_bi Psi + Psi' M_ib + Psi' M_ii Psi, (M_bi + Psi' M_ii) Phi; sym, I].
// No n x n dense matrix is formed: memory ~ the factor of K_ii plus n_i (n_b + m) doubles.
// Cost: one factorisation of K_ii, and the Lanczos iterations (a solve and a product per step).
#include <Eigen/Dense>
#include <vector>

#include "plant/superelement/residual_moments.hpp"
#include "plant/superelement/sparse_text.hpp"

namespace flexloop::plant::superelement {

struct CraigBampton {
  /// Reduced matrices: the interface DOFs in the order given, then the modal coordinates.
  Eigen::MatrixXd K, M;
  Eigen::Index interface_dofs = 0;
  /// The kept fixed-interface modes' frequencies, ascending (Hz).
  Eigen::VectorXd fixed_interface_hz;
  /// What the reduction leaves out, as moments of the unkept modes (residual_moments.hpp); empty
  /// unless asked for.
  ResidualMoments residual;
};

/// @throws std::invalid_argument for sizes that disagree, an interface row out of range or
/// repeated, a cut-off <= 0; std::domain_error when K_ii is not positive definite (the body
/// still moves with its interface held: hold it in the FE tool or add interface nodes) or M_ii
/// is not, or the Lanczos iteration does not converge.
/// `residual_block_solves` > 0: also the unkept modes' moments (residual_moments.hpp), with that
/// many more solves on the factor of K_ii (n_b right-hand sides each).
CraigBampton craig_bampton(const SparseMatrix& K, const SparseMatrix& M,
                           const std::vector<Eigen::Index>& interface_rows, double modes_up_to_hz,
                           int residual_block_solves = 0);

/// The natural frequencies (Hz, ascending) of the pencil (K, M) below `up_to_hz`, at most
/// `at_most` of them, by shift-invert Lanczos about a shift below the lowest (so a free body's
/// rigid-body modes, at 0 Hz, are found too). Small pencils (n <= 200) are solved dense.
/// @throws std::domain_error when K - sigma M or M is not positive definite, or no convergence.
Eigen::VectorXd sparse_natural_frequencies_hz(const SparseMatrix& K, const SparseMatrix& M,
                                              double up_to_hz, Eigen::Index at_most);

}  // namespace flexloop::plant::superelement
