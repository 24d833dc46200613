// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The deformation equations e = D(x) of a whole model, with exact first and second
// derivatives. Each element (and each 3-D rotational node's Euler-parameter normalisation) is a
// "deformation block" that depends on a few nodal coordinates; its Jacobian and Hessians are
// computed by forward-mode automatic differentiation (Eigen AutoDiff, nested for Hessians) on
// those local coordinates and scattered into the global arrays.
#include <Eigen/Dense>
#include <vector>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

struct DeformationBlock {
  int element = -1;         // element index, or -1 for an Euler normalisation
  int node = -1;            // node index of an Euler normalisation
  std::vector<int> coords;  // global coordinate indices, in the block's local order
  int first = 0;            // first deformation index in e
  int count = 0;
};

std::vector<DeformationBlock> deformation_blocks(const Model& m);

/// e = D(x), all deformations.
Eigen::VectorXd deformations(const Model& m, const std::vector<DeformationBlock>& blocks,
                             const Eigen::VectorXd& x);

/// The Jacobian D_x D (n_e x n_x).
Eigen::MatrixXd deformation_jacobian(const Model& m, const std::vector<DeformationBlock>& blocks,
                                     const Eigen::VectorXd& x);

/// sum_k w_k * Hessian(D_k)(x)  (n_x x n_x).
Eigen::MatrixXd weighted_deformation_hessian(const Model& m,
                                             const std::vector<DeformationBlock>& blocks,
                                             const Eigen::VectorXd& x, const Eigen::VectorXd& w);

/// The second directional derivative v^T Hessian(D_k)(x) v for every k (n_e).
Eigen::VectorXd deformation_curvature(const Model& m, const std::vector<DeformationBlock>& blocks,
                                      const Eigen::VectorXd& x, const Eigen::VectorXd& v);

/// Rows k = (Hessian(D_k)(x) v)^T: the directional derivative of the Jacobian, (n_e x n_x).
Eigen::MatrixXd deformation_hessian_times(const Model& m,
                                          const std::vector<DeformationBlock>& blocks,
                                          const Eigen::VectorXd& x, const Eigen::VectorXd& v);

/// Rows k = gradient over x of v^T Hessian(D_k)(x) v (third derivatives of D), (n_e x n_x).
Eigen::MatrixXd deformation_curvature_gradient(const Model& m,
                                               const std::vector<DeformationBlock>& blocks,
                                               const Eigen::VectorXd& x, const Eigen::VectorXd& v);

}  // namespace flexloop::plant::model
