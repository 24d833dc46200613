#pragma once
// The stationary covariance of a discrete system driven by white noise, on the modes strictly
// inside the unit circle:
//
//   x_{k+1} = A x_k + B n_k,  E[n n^T] = I,   P = A P A^T + B B^T,
//
// by Bartels-Stewart on an ordered real Schur form (Kitagawa's method, SLICOT's SB03MX): a
// fixed O(n^3), where the doubling iteration (numeric/stationary_covariance.hpp) needs log2(37/e)
// rounds of three n x n products for a mode at radius 1 - e (29 at e = 1e-7, the metrology
// frame's modes at 10 kHz).
//
// Modes on the unit circle (|lambda| >= 1 - tol: integrators of a force feedback without a leak,
// the floor's position) have no stationary covariance. They are split off along their invariant
// subspace: with the balanced A = Q [S11 S12; 0 S22] Q^T (LAPACK dgees, the k modes inside first)
// and S11 X - X S22 = -S12 (LAPACK dtrsyl), the part y = x1 - X x2 of the Schur coordinates
// evolves as y_{k+1} = S11 y_k + (B1 - X B2) n_k on its own (the spectral projector onto the
// modes inside, along those on the circle, is Q [I -X; 0 0] Q^T), and
//   P = T Q1 P11 Q1^T T,   S11 P11 S11^T - P11 = -(B1 - X B2)(B1 - X B2)^T  (SLICOT SB03MX),
// T the exact power-of-two balancing. The part on the circle starts at zero, as from rest; where
// the noise reaches it (B2 != 0) it drifts from there. No eigenvectors are formed: a Jordan block
// on the circle (a double integrator) or inside it (a delay chain) costs no accuracy.
#include <Eigen/Dense>

namespace flexloop::plant::lti {

struct StableCovariance {
  Eigen::MatrixXd P;           ///< the covariance of the part inside the circle, in x's coordinates
  Eigen::Index on_circle = 0;  ///< modes with 1 - tol <= |lambda| <= 1 + tol
  double driven =
      0;  ///< |the noise's part on the circle| / |B| (Frobenius): 0 when none reaches it
};

/// @throws std::invalid_argument when a mode lies outside the circle (|lambda| > 1 + tol: "the
/// loop is unstable"), when the Schur form does not converge or its order does not hold after
/// reordering (the modes on the circle are not resolved), or when the sizes do not close.
StableCovariance stable_covariance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double tol);

}  // namespace flexloop::plant::lti
