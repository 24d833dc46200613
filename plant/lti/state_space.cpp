// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/state_space.hpp"

#include <stdexcept>

namespace flexloop::plant::lti {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("state space: " + what);
}
std::string dims(const Eigen::MatrixXd& m) {
  return std::to_string(m.rows()) + "x" + std::to_string(m.cols());
}
}  // namespace

void StateSpace::validate() const {
  const auto n = A.rows();
  require(A.cols() == n, "A must be square, is " + dims(A));
  require(B.rows() == n, "B has " + std::to_string(B.rows()) + " rows, A has " + std::to_string(n));
  require(C.cols() == n,
          "C has " + std::to_string(C.cols()) + " columns, A has " + std::to_string(n));
  require(D.rows() == C.rows() && D.cols() == B.cols(), "D is " + dims(D) + ", expected " +
                                                            std::to_string(C.rows()) + "x" +
                                                            std::to_string(B.cols()));
  require(states.size() == static_cast<std::size_t>(n),
          "state label count differs from the state count");
  require(inputs.size() == static_cast<std::size_t>(B.cols()),
          "input label count differs from the input count");
  require(outputs.size() == static_cast<std::size_t>(C.rows()),
          "output label count differs from the output count");
  require(A.allFinite() && B.allFinite() && C.allFinite() && D.allFinite(),
          "a matrix entry is not finite");
}

}  // namespace flexloop::plant::lti
