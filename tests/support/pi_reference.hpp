// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The PI controller's reference for the runtime tests: its continuous state space discretised by
// the offline ZOH, with the parameters' feedthrough (identity when none) and limits (none when
// not one value for every channel).
#include <Eigen/Dense>
#include <limits>

#include "artefact/pi_parameters.hpp"
#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"
#include "tests/support/dynamic_reference.hpp"

namespace flexloop::test {

// The reference from the controller's continuous state space (xi' = -w_l xi + y,
// u = -(K_P y + K_I xi)) discretised by the offline ZOH (a matrix exponential), so the
// integrator coefficients a, b are not the runtime's formulas.
inline PiReference pi_reference(const artefact::PiParameters& p) {
  const Eigen::Index n = p.K_P.rows();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  plant::lti::StateSpace c{
      -p.leak_rad_s * I, I, -p.K_I, -p.K_P, numbered("xi", n), numbered("y", n), numbered("u", n)};
  const auto d =
      plant::lti::discretise(c, {plant::lti::DiscretisationMethod::kZeroOrderHold, p.dt, 0, false});
  const double inf = std::numeric_limits<double>::infinity();
  return PiReference{d.sys.A,
                     d.sys.B,
                     d.sys.C,
                     d.sys.D,
                     p.feedthrough.size() ? p.feedthrough : I,
                     p.u_min.size() == 1 ? Eigen::VectorXd::Constant(n, p.u_min(0))
                                         : Eigen::VectorXd::Constant(n, -inf),
                     p.u_max.size() == 1 ? Eigen::VectorXd::Constant(n, p.u_max(0))
                                         : Eigen::VectorXd::Constant(n, inf)};
}

}  // namespace flexloop::test
