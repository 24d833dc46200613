// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The consistent mass of a beam element with rotary inertia (mass_model = "beam"), as a frame
// element's in structural dynamics: the kinetic energy of a velocity field interpolated from the
// nodes, linear along the chord and cubic (Hermite) across it, plus that of the cross-section's
// rotation. With c = xq - xp, d = c / |c|, P = I - d d^T (across the chord), t_p, t_q the beam's
// axis at each node (carried by the node's rotation), xi in [0, 1], H2 = xi (1 - xi)^2,
// H4 = -xi^2 (1 - xi):
//   v(xi)    = (1 - xi) xp' + xi xq' + H2 (l0 t_p' - P c') + H4 (l0 t_q' - P c')
//   w_b(xi)  = d x v_xi(xi) / |c|                      bending rate of the section (v_xi = dv/dxi)
//   w_t(xi)  = d . ((1 - xi) w_p + xi w_q)             twist rate (3-D; w_p, w_q the nodes')
//   T = (rho A l0 / 2) int |v|^2 + (rho l0 / 2) int (w_b^T J w_b + (Iy + Iz) w_t^2)
// with J = Iy e_y e_y^T + Iz e_z e_z^T over the section axes (2-D: I about the plane's normal).
// On a straight beam this is Przemieniecki's consistent mass (Theory of Matrix Structural
// Analysis, 1968, §11.3-11.4: (m/420)[156 22l 54 -13l; ...] across, (m/6)[2 1; 1 2] along,
// rho I / (30 l)[36 3l -36 3l; ...] rotary, rho I_p l / 6 [2 1; 1 2] torsion); the bending
// frequencies of a cantilever converge as 1/n^4 with n elements (lumped masses: 1/n^2).
//
// The matrix depends on the configuration through d and the nodes' rotations. At rest (the
// operating points flexloop linearises at with this model) that is all the linearisation needs:
// the velocity terms of the inertia forces and their derivatives vanish there.
#include <Eigen/Dense>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

/// The element's mass matrix over (node p's coordinates, node q's coordinates) at configuration
/// x: 2 (dim + r) square, r = 1 rotation coordinate in 2-D, 4 Euler parameters in 3-D.
Eigen::MatrixXd beam_element_mass(const Model& m, const Element& el, const Eigen::VectorXd& x);

}  // namespace flexloop::plant::model
