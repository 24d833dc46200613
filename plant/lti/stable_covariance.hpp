// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The stationary covariance of a discrete system driven by white noise, on the modes strictly
// inside the unit circle:
//
//   x_{k+1} = A x_k + B n_k,  E[n n^T] = I,   P = A P A^T + B B^T,
//
// by Hammarling's method on an ordered real Schur form (SLICOT's SB03OD, for the Cholesky factor
// of P): a fixed O(n^3), where the doubling iteration (numeric/stationary_covariance.hpp) needs
// log2(37/e) rounds of three n x n products for a mode at radius 1 - e (29 at e = 1e-7, the
// metrology frame's modes at 10 kHz).
//
// Modes on the unit circle (|lambda| >= 1 - tol: integrators of a force feedback without a leak,
// the floor's position, undamped structural modes) have no stationary covariance. They are split
// off along their invariant subspace: with the balanced A = Q [S11 S12; 0 S22] Q^T (LAPACK dgees,
// the k modes inside first) and S11 X - X S22 = -S12 (LAPACK dtrsyl), the part y = x1 - X x2 of
// the Schur coordinates evolves as y_{k+1} = S11 y_k + (B1 - X B2) n_k on its own (the spectral
// projector onto the modes inside, along those on the circle, is Q [I -X; 0 0] Q^T), and
//   P = T Q1 U U^T Q1^T T,   S11 (U U^T) S11^T - U U^T = -(B1 - X B2)(B1 - X B2)^T,
// U the upper-triangular Cholesky factor solved for directly by Hammarling's method (SLICOT
// SB03OD), T the exact power-of-two balancing. Solving for the factor keeps P positive
// semidefinite by construction: a Bartels-Stewart P of a loop whose lightly damped modes sit at
// 1 - |lambda| ~ 1e-9 (an undamped arm at 10 kHz) loses its definiteness to rounding at the 1e-5
// level of its largest eigenvalue, by amounts that change with the BLAS kernel. The part on the
// circle starts at zero, as from rest; where the noise reaches it (B2 != 0) it drifts from there.
// No eigenvectors are formed: a Jordan block on the circle (a double integrator) or inside it (a
// delay chain) costs no accuracy.
//
// What no algorithm removes: the variance of a mode at radius 1 - e is about |b|^2 / (2 e), so a
// change d of the mode's radius moves it by d / e relative, and a pole of the balanced A is known
// only to about eps ||A|| (times its condition number): the backward error of any solver, and
// what another BLAS kernel's rounding changes. `sensitivity` = eps ||S11||_F / min e is that
// first-order figure. Measured (tests/hard_cases/blas_kernels.sh, six OpenBLAS kernels, AMD EPYC,
// 2026-12-07): the generated 50-beam arm, whose 8.5 Hz bending pair has e = 3.4e-9 (zeta 6e-7: no
// damping but the struts' at its root), states 3.2e-6 and its start moves by up to 2.4e-6 between
// kernels; the metrology frame states 1.4e-10 and moves by 3.4e-10 (open loop), 1.2e-11 and
// 3.1e-11 (closed). The test allows 10 times the stated figure (and at least 1e-10).
#include <Eigen/Dense>

namespace flexloop::plant::lti {

struct StableCovariance {
  Eigen::MatrixXd P;       ///< the covariance of the part inside the circle, in x's coordinates
  Eigen::MatrixXd factor;  ///< n x k: P = factor factor^T (T Q1 U), k the modes inside
  Eigen::MatrixXd stable_noise;  ///< n x m: the noise of the part inside (the projector times B),
                                 ///< P = A P A^T + stable_noise stable_noise^T
  Eigen::Index on_circle = 0;    ///< modes with 1 - tol <= |lambda| <= 1 + tol
  double sensitivity = 0;        ///< relative change of P to expect from rounding A (see above)
  double driven =
      0;  ///< |the noise's part on the circle| / |B| (Frobenius): 0 when none reaches it
};

/// @throws std::invalid_argument when a mode lies outside the circle (|lambda| > 1 + tol: "the
/// loop is unstable"), when the Schur form does not converge or its order does not hold after
/// reordering (the modes on the circle are not resolved), or when the sizes do not close.
StableCovariance stable_covariance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double tol);

}  // namespace flexloop::plant::lti
