// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Modal analysis of the linearised equations of motion
//   M q'' + (C + D) q' + (K + N + G) q = f          (doc/design.md §3, bars omitted)
// and of a state space.
//
// Natural modes: undamped free vibration q = phi e^{j w t} gives the generalised eigenproblem
//   (K - w^2 M) phi = 0,   det(K - w^2 M) = 0,
// with K the total stiffness (K + N + G). M must be symmetric positive definite, judged by a
// Cholesky of M scaled to a unit diagonal (every pivot above 100 n eps), not by its eigenvalue
// spread: a lumped beam chain with small rotary inertias is definite at condition 1e11. When K is
// symmetric the problem is symmetric-definite (Eigen::GeneralizedSelfAdjointEigenSolver): w^2 is
// real and the shapes satisfy Phi^T M Phi = I and Phi^T K Phi = diag(w^2). With K definite too
// (the same scaled Cholesky) it is solved as M phi = (1 / w^2) K phi, which gives every w^2 to its
// own relative accuracy (a 400-beam chain's first w^2 = 9e2 beside its largest 1.6e14); otherwise
// (rigid-body modes, beyond buckling) through the Cholesky of M, each w^2 to eps max|w^2|. When K
// is not symmetric (N from a moving configuration, or non-conservative loads) the general real QZ
// algorithm is used (Eigen::GeneralizedEigenSolver); w^2 may then be complex (flutter).
//
// Sign convention for frequencies_hz (|f| = sqrt(|w^2|) / (2 pi)):
//   w^2 real and > 0      : f > 0, an undamped oscillation at f Hz;
//   |w^2| negligible      : f = 0, a rigid-body (mechanism) mode; "negligible" means
//                           |w^2| <= 100 n eps max_i |w_i^2|, i.e. within rounding (never with
//                           K definite: then every w^2 is resolved);
//   w^2 real and < 0      : f < 0, divergence (static instability, e.g. beyond buckling):
//                           real poles s = +-2 pi |f|, so 2 pi |f| is the e-folding rate [1/s];
//   w^2 complex (flutter) : f < 0 as well, with |f| = |w^2|^(1/2) / (2 pi); the exact value is in
//                           omega_squared. "Complex" means |Im w^2| > sqrt(eps) max_i |w_i^2|.
// So f < 0 always flags an unstable mode. Modes are sorted by f ascending (unstable first).
//
// Buckling: with G the geometric stiffness of a reference load, the load multipliers lambda at
// which the structure loses stiffness solve det(K + lambda G) = 0.
//
// Poles: eigenvalues of A.
#include <Eigen/Dense>
#include <string>

#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

struct Modes {
  Eigen::VectorXd frequencies_hz;  ///< signed, see the convention above; ascending
  Eigen::MatrixXd shapes;  ///< column i belongs to frequencies_hz(i); phi_i^T M phi_i = 1, its
                           ///< largest-magnitude entry positive. For a flutter mode: the real part
                           ///< of the complex shape after turning its largest entry real.
  Eigen::VectorXcd omega_squared;  ///< the eigenvalues w^2 [rad^2/s^2] in the same order
};

/// Natural frequencies and mass-normalised mode shapes of (K - w^2 M) phi = 0.
/// @throws std::invalid_argument when the sizes differ, an entry is not finite, M is not
///         symmetric, M is indefinite, or M is singular (massless coordinates: condense them
///         out or give them mass); the message says which.
Modes natural_modes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K);

/// Finite real load multipliers lambda with det(K + lambda G) = 0, sorted by |lambda| (the
/// critical multiplier first; a negative lambda means buckling under the reversed load). G may
/// be singular (unloaded coordinates give infinite multipliers, which are left out) or
/// indefinite. Complex multipliers (non-symmetric K) are left out. Symmetric positive definite K
/// with symmetric G: solved as G x = mu K x (symmetric-definite, mu = -1/lambda, mu = 0 left out);
/// otherwise by the QZ algorithm on the pencil (K, -G).
/// @throws std::invalid_argument on size mismatch, non-finite entries, or a singular pencil
///         (K + lambda G singular for every lambda).
Eigen::VectorXd buckling_multipliers(const Eigen::MatrixXd& K, const Eigen::MatrixXd& G);

/// Static stability of an undamped linearised model (doc/design.md §9, near-buckling preload). At a
/// stationary configuration a mode diverges where the total stiffness K + N + G (condensed, when
/// massless coordinates were) has a negative eigenvalue: w^2 < 0, f < 0 in Modes; a mode with a
/// complex w^2 (non-symmetric stiffness) flutters. With a preload (G not negligible against K)
/// the first buckling multiplier lambda_cr of det(K + lambda G) = 0 says how far the load is from
/// buckling: the preload is 1/lambda_cr times the first buckling load, beyond it for lambda_cr < 1.
struct StaticStability {
  int divergent = 0;         ///< modes with a real w^2 < 0
  int flutter = 0;           ///< modes with a complex w^2
  double growth_rate = 0.0;  ///< [1/s] of the fastest unstable mode, max Re sqrt(-w^2); 0: stable
  bool preloaded = false;    ///< |G| > 1e-12 |K|
  /// buckling_multipliers(K, G) when preloaded; empty without a preload, when none is finite and
  /// real, or when K + lambda G is singular for every lambda (a mechanism the preload leaves).
  Eigen::VectorXd buckling_multipliers;
  /// The smallest non-negative of them (0: the unloaded structure is a mechanism there); negative
  /// when there is none.
  double critical_multiplier = -1.0;
  bool stable() const { return divergent == 0 && flutter == 0; }
};

/// From the modes of (M, K + N + G) and the passive stiffness K and geometric stiffness G of the
/// same dynamic coordinates (uncondensed: buckling is static, the mass plays no role).
StaticStability static_stability(const Modes& modes, const Eigen::MatrixXd& K,
                                 const Eigen::MatrixXd& G);

/// One sentence. Unstable, e.g.: "the preload is 1.49 times the first buckling load (buckling
/// multiplier 0.672): the linearised model is statically unstable, 1 divergent mode growing as
/// e^(25.3 t) (a disturbance doubles every 0.0274 s)"; stable: "statically stable" and the
/// buckling multiplier, or "no preload".
std::string to_string(const StaticStability& s);

/// Eigenvalues of sys.A sorted by |imag| ascending, then real ascending, then imag ascending
/// (so a conjugate pair appears as p, conj(p) with negative imaginary part first).
/// @throws std::invalid_argument when sys.validate() fails; std::runtime_error when the
///         eigensolver does not converge.
Eigen::VectorXcd poles(const StateSpace& sys);

}  // namespace flexloop::plant::lti
