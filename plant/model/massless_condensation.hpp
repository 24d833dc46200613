// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Exact static (Guyan) condensation of massless directions of the linearised equations
//   M q'' + D q' + (K + G) q = f        (dynamic block, doc/design.md §3; bars omitted)
//
// Why. Beams with lumped translational masses and no rotational inertia leave the nodal
// rotations (and so the bending deformations that move them) massless: M is singular and
// M^-1 (state space, natural_modes) does not exist.
//
// Method. M (symmetric positive semi-definite) = V diag(mu) V^T. Directions with
// mu_i <= relative_mass_tolerance * max(mu) are massless: Z (n x n_b) spans them, Y (n x n_a)
// the others, [Y Z] orthonormal. Write q = Y a + Z b. With K_t = K + G (the total stiffness of
// the dynamics, including the geometric stiffness of the preload) the rows Z^T of the equations
// read, since M Z = 0,
//   Z^T K_t Y a + Z^T K_t Z b + Z^T D (Y a' + Z b') = Z^T f.
// Without forces on the massless directions (Z^T f = 0) and without damping there
// (Z^T D = 0) this is algebraic: b = -(Z^T K_t Z)^-1 Z^T K_t Y a, so
//   q = T a,   T = Y - Z (Z^T K_t Z)^-1 Z^T K_t Y,   a = Y^T q,
// and substituting into the Y^T rows (equivalently, projecting with T^T: Z^T K_t T = 0 and
// M Z = 0, so T^T K_t T = Y^T K_t T and T^T M T = Y^T M Y, whether or not K_t is symmetric)
//   M_a = Y^T M Y,  K_a = T^T K T,  G_a = T^T G T,  D_a = T^T D T,  f_a = T^T f.
// K_a + G_a = T^T K_t T is the Schur complement of K_t on the massless block.
//
// Contract.
// - Exact for the undamped dynamics: the eigenvalues w^2 of
//   (K_a + G_a, M_a) are exactly the finite eigenvalues of (K_t, M), and T maps the reduced mode
//   shapes to the full ones. Directions dropped by the tolerance are treated as having zero mass
//   (M_a = Y^T M Y ignores their mass mu_i, which is below the tolerance).
// - Geometric stiffness: T is built with K_t = K + G at the given load, so it is exact at that
//   load only. Do NOT compute buckling multipliers det(K_a + lambda G_a) = 0 from the reduced
//   matrices (T depends on lambda); buckling is static and needs no mass: use the uncondensed
//   K, G.
// - Damping in the massless directions (Z^T D != 0, e.g. viscous damping on the bending
//   deformations of a beam with lumped masses) makes b obey a first-order equation; no
//   second-order model in a alone reproduces that exactly. Policy kProject (default): D is
//   projected with the static T, D_a = T^T D T; this keeps the dissipation of every motion that
//   follows the static shape and neglects the relaxation lag of b (time constants of
//   (Z^T K_t Z)^-1 Z^T D Z), which is small for the light structural damping the model file
//   describes. damping_coupling reports ||Z^T D||_F / ||D||_F so a caller can see it. Policy
//   kRefuse: throw std::invalid_argument instead when damping_coupling >
//   relative_damping_tolerance.
// - Applied forces/inputs on massless directions enter as q = T a + Z (Z^T K_t Z)^-1 Z^T f
//   (a static feedthrough); mapping inputs is the caller's job (f_a = T^T f for the a-rows).
//
// Errors (std::invalid_argument): sizes differ or entries are not finite; M not symmetric or
// indefinite (an eigenvalue below -relative_mass_tolerance * max(mu)); M zero (everything
// massless); Z^T K_t Z singular (smallest singular value <= relative_stiffness_tolerance times
// the largest singular value of K_t): a massless mechanism, a motion that costs neither
// inertia nor strain energy; the message names the participating coordinates (labels if given).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "plant/model/linearisation.hpp"

namespace flexloop::plant::model {

enum class MasslessDampingPolicy { kProject, kRefuse };

struct CondensationOptions {
  double relative_mass_tolerance = 1e-10;
  double relative_stiffness_tolerance = 1e-12;
  MasslessDampingPolicy damping = MasslessDampingPolicy::kProject;
  double relative_damping_tolerance = 1e-12;  // for kRefuse
};

struct MasslessCondensation {
  Eigen::MatrixXd M, K, D, G;     ///< reduced matrices in the massive coordinates a (n_a x n_a)
  Eigen::MatrixXd T;              ///< q = T a (n x n_a)
  Eigen::MatrixXd Y, Z;           ///< orthonormal bases of the massive and massless directions
  int massless_count = 0;         ///< n_b = columns of Z
  double damping_coupling = 0.0;  ///< ||Z^T D||_F / ||D||_F (0: the condensation is exact)
};

/// Condense the massless directions of (M, D, K, G), all n x n (D and G may be empty = zero).
/// `labels` (optional, n entries) name the coordinates in error messages.
MasslessCondensation condense_massless(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K,
                                       const Eigen::MatrixXd& D, const Eigen::MatrixXd& G,
                                       const CondensationOptions& options = {},
                                       const std::vector<std::string>& labels = {});

/// The dynamic block (first m.nd() rows and columns) of a stationary linearisation. Throws
/// std::invalid_argument if C or N is non-zero there (a moving operating point: condense
/// M, C + D, K + N + G with the matrix overload).
MasslessCondensation condense_massless(const Model& m, const Linearisation& lin,
                                       const CondensationOptions& options = {});

}  // namespace flexloop::plant::model
