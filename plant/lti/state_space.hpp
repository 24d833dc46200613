// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A labelled continuous-time linear time-invariant system
//   dz/dt = A z + B u,   y = C z + D u
// with one label per state, input and output. The offline currency between linearisation,
// analysis, controller design and discretisation.
#include <Eigen/Dense>
#include <string>
#include <vector>

namespace flexloop::plant::lti {

struct StateSpace {
  Eigen::MatrixXd A, B, C, D;
  std::vector<std::string> states, inputs, outputs;

  Eigen::Index nx() const { return A.rows(); }
  Eigen::Index nu() const { return B.cols(); }
  Eigen::Index ny() const { return C.rows(); }

  /// Throws std::invalid_argument when the matrix sizes or label counts disagree, or when an
  /// entry is not finite.
  void validate() const;
};

}  // namespace flexloop::plant::lti
