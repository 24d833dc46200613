// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Linearised equations of motion about an operating point (doc/design.md §3):
//   Mbar dq'' + (Cbar + Dbar) dq' + (Kbar + Nbar + Gbar) dq = DF(x)^T df - DF(e)^T dsigma_a
// from the nonlinear equations in the generalised coordinates q,
//   R(q, q', q'') = DF(x)^T (g_in(x, x', x'') - f) + DF(e)^T sigma = 0,
//   x = F(x)(q), x' = DF(x) q', x'' = DF(x) q'' + D2F(x) q' q',
//   sigma = sigma_a + S e + S_d e' (flexible and released deformations).
// Every matrix is an exact derivative of R:
//   Mbar = dR/dq'' = DF^T M DF,  Dbar = DF(e)^T S_d DF(e),  Cbar = dR/dq' - Dbar,
//   Kbar = DF(e)^T S DF(e),
//   Gbar = DF^T [ sum_k sigma_k Hess(D_k) ] DF: the derivative of DF(x)^T a + DF(e)^T sigma at
//          frozen a = g_in - f and sigma, where sigma of the rigid and generalised deformations
//          is the stress that balances the nodal forces (equations of reaction),
//   Nbar = dR/dq - Kbar - Gbar (velocity and acceleration terms; zero at a stationary point).
// The second-order geometric transfer function enters Gbar through the Lagrangian form of
// implicit differentiation, with element Hessians from nested automatic differentiation; at a
// moving operating point, Cbar and Nbar need D2F(x) q' and D3F(x) q' q', obtained by
// differentiating the velocity and acceleration constraints once more (third derivatives of the
// deformations by three-level nested AD, contracted twice with x').
#include <Eigen/Dense>

#include "plant/model/configuration.hpp"
#include "plant/model/model.hpp"

namespace flexloop::plant::model {

struct OperatingPoint {
  Eigen::VectorXd q, qd,
      qdd;  // generalised coordinates and their rates (n_q); empty = reference, zero
  Eigen::VectorXd sigma_a;  // actuator stresses (n_e); empty = zero
};

struct Linearisation {
  Eigen::VectorXd q, qd, qdd;  // the operating point
  Eigen::VectorXd x, xd, xdd;  // nodal coordinates and rates there
  Eigen::VectorXd sigma_a;     // actuator stresses of the operating point (n_e)
  Eigen::VectorXd e, ed,
      sigma;                 // deformations, rates, stresses (rigid/generalised: from equilibrium)
  Eigen::VectorXd f;         // applied nodal forces
  Eigen::MatrixXd J;         // D_x D (n_e x n_x)
  Eigen::MatrixXd DFx, DFe;  // first-order geometric transfer functions (n_x x n_q, n_e x n_q)
  Eigen::MatrixXd Vx;        // d(x')/dq = D2F(x) q' (n_x x n_q); zero when stationary
  Eigen::MatrixXd Wx;        // d(x'')/dq = D2F(x) q'' + D3F(x) q' q'; zero when stationary
  Eigen::MatrixXd Zx;        // d(x'')/dq' = 2 D2F(x) q'; zero when stationary
  Eigen::MatrixXd Ved;       // d(e')/dq; zero when stationary
  Eigen::MatrixXd Mx;        // nodal mass matrix M(x)
  Eigen::MatrixXd S, Sd;     // global stiffness and damping of the deformations (n_e x n_e)
  Eigen::MatrixXd M, C, D, K, N, G;  // the linearised matrices (n_q x n_q)
};

/// Linearise about `op`. Throws flexloop::InputError for a kinematic singularity.
Linearisation linearise(const Model& m, const OperatingPoint& op = {});

/// The nonlinear kinematics at (q, q', q''): x = F(x)(q), x' = DF q', x'' = DF q'' + D2F q' q',
/// with the deformation Jacobian J and DF(x) there.
struct NodalMotion {
  Eigen::VectorXd x, xd, xdd;
  Eigen::MatrixXd J, DF;
};
NodalMotion nodal_motion(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         const Eigen::VectorXd& qdd);

/// The nonlinear residual R(q, q', q'') of the equations of motion (n_q), for tests and
/// equilibrium iterations.
Eigen::VectorXd equations_of_motion_residual(const Model& m, const Eigen::VectorXd& q,
                                             const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                             const Eigen::VectorXd& sigma_a = {});

/// Global stiffness S and damping S_d (n_e x n_e, block diagonal over elements).
void global_constitutive(const Model& m, Eigen::MatrixXd& S, Eigen::MatrixXd& Sd);

/// The operating point the model file asks for ([configuration]; reference and at rest if absent).
OperatingPoint model_operating_point(const Model& m);

/// Reference (undeformed) generalised coordinates q0.
Eigen::VectorXd reference_generalised(const Model& m);

}  // namespace flexloop::plant::model
