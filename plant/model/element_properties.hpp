// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Element stiffness (for the deformations of element_kinematics.hpp) and translational mass.
//
// Stiffness. For small deformations the Euler-Bernoulli strain energy of a prismatic beam
// element with end rotations theta_p, theta_q relative to the chord (same sense) is
//   U = (2 EI / l0) (theta_p^2 + theta_p theta_q + theta_q^2)
// (slope-deflection equations M_p = (EI/l0)(4 theta_p + 2 theta_q), M_q = (EI/l0)(2 theta_p +
// 4 theta_q)); torsion U = GJ phi^2 / (2 l0); extension U = EA e1^2 / (2 l0). With the unscaled
// SPACAR deformations (e_bend = -/+ l0 theta, e2 = l0 phi; see element_kinematics.hpp):
//   S = diag( EA/l0,  GJ/l0^3,  (EIy/l0^3) [4 -2; -2 4],  (EIz/l0^3) [4 -2; -2 4] )
// for (e1, e2, e3, e4, e5, e6), so U = e^T S e / 2. The generalised stresses are then
// sigma1 = normal force, sigma2 = torque / l0, and for a bending pair l0 sigma = the bending
// moment at that end (sign as the deformation). e3, e4 bend about the section's y axis (Iy =
// integral of z^2 dA), e5, e6 about z (Iz). The planar beam has the same bending block with
// I about the out-of-plane axis.
//
// Mass. Element mass on the translational nodal coordinates only, ordering (xp, xq):
// lumped m/2 per end; consistent (linear interpolation of the translations along the element)
// (m/6) [2I I; I 2I].
#include <Eigen/Dense>

namespace flexloop::plant::model {

/// SI units; rho = density (kg/m^3), mass per length = rho A.
struct BeamSection {
  double E, G, A, Iy, Iz, J;
  double rho;
};

/// S (6x6) such that sigma = S e for the spatial beam deformations, all flexible. Throws
/// std::invalid_argument if l0 <= 0.
Eigen::Matrix<double, 6, 6> spatial_beam_stiffness(const BeamSection& s, double l0);

/// S (3x3) for the planar beam (e1 elongation, e2, e3 bending), I about the out-of-plane axis.
/// Throws std::invalid_argument if l0 <= 0.
Eigen::Matrix3d planar_beam_stiffness(double E, double A, double I, double l0);

/// Element mass on translational coordinates, (2 dim) x (2 dim), ordering (xp, xq). Throws
/// std::invalid_argument unless dim is 2 or 3 and mass >= 0.
Eigen::MatrixXd element_translational_mass(double mass, int dim /*2 or 3*/, bool consistent);

}  // namespace flexloop::plant::model
