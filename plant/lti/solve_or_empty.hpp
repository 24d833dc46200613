// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <Eigen/Dense>

namespace flexloop::plant::lti {

// X = decomposition^-1 rhs, where either side may be empty (a loop without controller states, a
// model without massive coordinates). Eigen 3.4's triangular solves bind a reference to the first
// coefficient even of an empty block, which is undefined behaviour on its null data pointer
// (UBSan: "reference binding to null pointer"); the empty answer needs no solve.
template <class Decomposition, class Rhs>
Eigen::MatrixXd solve_or_empty(const Decomposition& decomposition,
                               const Eigen::MatrixBase<Rhs>& rhs) {
  if (decomposition.rows() == 0 || rhs.size() == 0)
    return Eigen::MatrixXd::Zero(decomposition.cols(), rhs.cols());
  return decomposition.solve(rhs);
}

}  // namespace flexloop::plant::lti
