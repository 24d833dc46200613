// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Offline: a discrete plant  x_{k+1} = Ad x_k + Bd u_k,  y_k = Cd x_k + Dd u_k  in real modal
// (real block-diagonal) coordinates  x = T z:
//
//   z_{k+1} = Λ z_k + Bm u_k,   y_k = Cm z_k + Dd u_k,   Λ = T^-1 Ad T,  Bm = T^-1 Bd,  Cm = Cd T,
//
// Λ has a 1x1 block λ for each real eigenvalue and a 2x2 block [[a, b], [-b, a]] for each
// complex pair a ± jb (columns Re v, Im v of T for the eigenvector v of a + jb), so the online
// dynamics cost O(n) instead of O(n²) (plant/runtime/modal_plant.hpp). Input and output matrices
// stay dense.
//
// Accuracy. At 10 kHz the poles crowd near z = 1 (the metrology frame's 13.9 Hz pair has
// 1 - |z| = 1.2e-5), and a lightly damped mode turns an absolute pole error ε into a relative
// response error of about ε / (1 - |z|). Eigenvalues of Ad itself carry an error of
// eps ||Ad|| ≈ 1e-15 (||Ad|| ~ 10 in physical units): 1e-10 in the response. So the decomposition
// works on  Δ = Ad - I  (exact in floating point for the entries near 1), balanced by an exact
// power-of-two diagonal similarity (Parlett-Reinsch, as LAPACK's gebal), where the pole error is
// eps ||balanced Δ|| ~ 1e-18; and the result keeps  Λ - I  (Lambda_minus_I), which the runtime
// steps with (z + ((Λ - I) z + Bm u)), since rounding a ≈ 0.99995 to double would cost 1e-16
// again. Lambda = I + Lambda_minus_I is kept for readers.
//
// Eigenvectors are those of Eigen::EigenSolver on the balanced Δ, mapped back, each complex one
// rotated so that Re v ⟂ Im v, and every column scaled to unit norm. Repeated eigenvalues (the
// metrology frame's symmetric 13.9/13.9 Hz and 31.3/31.3 Hz pairs, integrator poles at z = 1) are
// fine as long as Ad is diagonalisable: eigenvalues that come out equal to within
// 8 eps ||balanced Δ|| get an orthonormal basis of the span of their computed eigenvectors.
//
// The floor's own position and velocity (states "pos:<c>", "vel:<c>" for an input "acc:<c>",
// gravity preload) are a 2x2 Jordan block [[1, t], [0, 1]] each: they are kept as such, as blocks
// [[0, t], [0, 0]] of Λ - I beside the structure's pairs, and the structure is decoupled from them
// by the Sylvester equation Ad_SS X - X Ad_FF = -Ad_SF (solved in the structure's modal
// coordinates): its modal state is its motion relative to the floor.
//
// Refusal (std::invalid_argument, saying to use the dense form): any other defective or nearly
// defective Ad (a Jordan block, e.g. a double integrator that is not the floor's) shows as
//   cond_2(V) > max_condition, V the unit-column eigenvector matrix of the balanced Δ
//   (default 1e7. The modal plant's error grows as cond_2(V) eps, at most 2e-9 relative here.
//   A Jordan block known only up to rounding, as the ZOH of a critically damped pair, computes
//   at about 1/sqrt(eps) ~ 1e8, and one of size 3 at 9e7: both ten times above it), or
//   ||Δ T - T (Λ - I)||_F > 1e-10 ||Δ||_F ||T||_F   (T is not an eigenbasis),
// or as the eigen-decomposition failing to converge. Inconsistent or non-finite input also throws.
#include <Eigen/Dense>
#include <vector>

#include "plant/lti/discretise.hpp"

namespace flexloop::plant::lti {

struct ModalForm {
  Eigen::MatrixXd Lambda_minus_I;  ///< Λ - I, real block-diagonal, n x n: what the runtime uses
  Eigen::MatrixXd Lambda;          ///< Λ = I + (Λ - I), for readers
  Eigen::MatrixXd B, C, D;         ///< Bm = T^-1 Bd, Cm = Cd T, D = Dd
  Eigen::MatrixXd T;               ///< physical state x = T z
  std::vector<int> block_sizes;    ///< 1 or 2, along the diagonal of Λ: the 2s first
  double dt = 0;
  double eigenvector_condition = 0;  ///< cond_2 of the balanced eigenvector matrix V
};

struct ModalFormOptions {
  double max_condition = 1e7;  ///< refuse when cond_2(V) exceeds this
};

/// @throws std::invalid_argument as described above, and for a structure with a pole at z = 1 of
/// its own beside the floor's blocks.
ModalForm to_modal_form(const DiscreteStateSpace& d, const ModalFormOptions& options = {});

}  // namespace flexloop::plant::lti
