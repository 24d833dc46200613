// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Nodal inertia and applied forces in nodal coordinates x.
//  - translations: lumped node masses plus element masses (lumped: half per end; consistent:
//    linear interpolation), constant;
//  - beam elements with mass_model = "beam": their consistent mass with rotary inertia over both
//    nodes' translations and rotations (beam_mass.hpp), which depends on the configuration; their
//    weight acts half at each end;
//  - 2-D rotational node: J phi'';
//  - 3-D rotational node with Euler parameters lambda, body angular velocity w' = 2 L(lambda)
//  lambda':
//    Lagrange's equations of T = 2 lambda'^T L^T J L lambda' give the inertia force
//        4 L^T J L lambda'' + 8 L(lambda')^T J L(lambda) lambda'
//    (Nikravesh, Computer-Aided Analysis of Mechanical Systems, 1988, §11.4).
#include <Eigen/Dense>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

/// M(x), n_x x n_x.
Eigen::MatrixXd mass_matrix(const Model& m, const Eigen::VectorXd& x);

/// Applied nodal forces f (gravity on all translational mass, plus node forces), n_x.
Eigen::VectorXd applied_forces(const Model& m);

/// Inertia forces M(x) xdd + h(x, xd), n_x.
Eigen::VectorXd inertia_forces(const Model& m, const Eigen::VectorXd& x, const Eigen::VectorXd& xd,
                               const Eigen::VectorXd& xdd);

/// L(lambda): w' = 2 L(lambda) lambda'.
Eigen::Matrix<double, 3, 4> euler_l_matrix(const Eigen::Vector4d& l);

}  // namespace flexloop::plant::model
