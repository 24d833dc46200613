// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Kinematic analysis (doc/design.md §3): the dependent nodal coordinates x(c) from the generalised
// coordinates q by Newton iteration on the rigid and generalised deformation equations
//   G(x) = [D_o(x); D_m(x)] = [0; e_m(q)],
// and the first-order geometric transfer function DF(x) = dx/dq by implicit differentiation:
//   J_gc dx_c = P_e dq - J_gm P_x dq.
#include <Eigen/Dense>
#include <vector>

#include "plant/model/kinematics.hpp"
#include "plant/model/model.hpp"

namespace flexloop::plant::model {

/// Index sets of the partition and the map between q and (x, e).
struct Partition {
  std::vector<int> x_fixed, x_dependent, x_generalised;  // coordinate indices
  std::vector<int> e_rigid, e_generalised, e_dependent;  // deformation indices
  std::vector<int> g_rows;         // deformation rows of G: rigid, then generalised
  std::vector<int> q_coordinate;   // per q: coordinate index, or -1
  std::vector<int> q_deformation;  // per q: deformation index, or -1
};

Partition make_partition(const Model& m);

/// Generalised coordinates of a nodal configuration x (x(m) values and e(m) = D_m(x)).
Eigen::VectorXd generalised_from_x(const Model& m, const Partition& p,
                                   const std::vector<DeformationBlock>& blocks,
                                   const Eigen::VectorXd& x);

/// x(q) by Newton iteration from `guess`; x(o) taken from `guess`. Throws flexloop::InputError
/// naming coordinates and deformations when the kinematic Jacobian is singular, and
/// std::runtime_error when Newton does not converge.
Eigen::VectorXd solve_configuration(const Model& m, const Partition& p,
                                    const std::vector<DeformationBlock>& blocks,
                                    const Eigen::VectorXd& q, const Eigen::VectorXd& guess);

/// DF(x) = dx/dq (n_x x n_q) at a configuration, given the deformation Jacobian J = D_x D there.
Eigen::MatrixXd geometric_transfer(const Model& m, const Partition& p, const Eigen::MatrixXd& J);

/// Second-order term D2F(x) qd qd: the nodal accelerations when q'' = 0, given x, DF and qd.
Eigen::VectorXd convective_acceleration(const Model& m, const Partition& p,
                                        const std::vector<DeformationBlock>& blocks,
                                        const Eigen::VectorXd& x, const Eigen::MatrixXd& J,
                                        const Eigen::VectorXd& xdot);

}  // namespace flexloop::plant::model
