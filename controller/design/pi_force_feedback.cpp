// SPDX-License-Identifier: BSD-3-Clause
#include "controller/design/pi_force_feedback.hpp"

#include <cmath>
#include <stdexcept>

namespace flexloop::controller::design {

namespace {

void require_valid_settings(const PiForceFeedbackSettings& s, const char* who) {
  if (!(s.omega_d_rad_s > 0) || !(s.zeta > 0) || !(s.leak_rad_s >= 0) ||
      !std::isfinite(s.omega_d_rad_s) || !std::isfinite(s.zeta) || !std::isfinite(s.leak_rad_s))
    throw std::invalid_argument(std::string(who) +
                                ": need omega_d > 0, zeta > 0 and leak >= 0 (finite)");
}

bool finite_positive(double v) {
  return std::isfinite(v) && v > 0;
}

}  // namespace

PiGains design_pi_force_feedback(const Eigen::MatrixXd& Mdd, const Eigen::MatrixXd& Kdd,
                                 const PiForceFeedbackSettings& s) {
  const Eigen::Index n = Mdd.rows();
  if (Mdd.cols() != n || Kdd.rows() != n || Kdd.cols() != n || n == 0)
    throw std::invalid_argument("design_pi_force_feedback: Mdd and Kdd must be square, same size");
  require_valid_settings(s, "design_pi_force_feedback");
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Mdd);
  if (!lu.isInvertible())
    throw std::invalid_argument("design_pi_force_feedback: the mass matrix Mdd is singular");
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  PiGains g;
  g.settings = s;
  g.K_P = lu.solve(Kdd) / (s.omega_d_rad_s * s.omega_d_rad_s) - I;
  g.K_I = 2.0 * s.zeta * s.omega_d_rad_s * (I + g.K_P);
  return g;
}

PiGains design_pi_force_feedback_per_strut(const std::vector<CollocatedStrut>& struts,
                                           const PiForceFeedbackSettings& s) {
  if (struts.empty()) throw std::invalid_argument("design_pi_force_feedback_per_strut: no struts");
  require_valid_settings(s, "design_pi_force_feedback_per_strut");
  const auto n = static_cast<Eigen::Index>(struts.size());
  const double wd2 = s.omega_d_rad_s * s.omega_d_rad_s;
  Eigen::VectorXd k_p(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const CollocatedStrut& c = struts[static_cast<std::size_t>(i)];
    if (!finite_positive(c.stiffness) || !finite_positive(c.inverse_mass))
      throw std::invalid_argument("design_pi_force_feedback_per_strut: strut " +
                                  std::to_string(i + 1) +
                                  " needs a finite positive stiffness and inverse mass");
    k_p(i) = c.stiffness * c.inverse_mass / wd2 - 1.0;
  }
  PiGains g;
  g.settings = s;
  g.K_P = k_p.asDiagonal();
  g.K_I = (2.0 * s.zeta * s.omega_d_rad_s * (k_p.array() + 1.0)).matrix().asDiagonal();
  return g;
}

plant::lti::StateSpace pi_state_space(const PiGains& g, const std::vector<std::string>& sensors,
                                      const std::vector<std::string>& actuators) {
  const Eigen::Index n = g.K_P.rows();
  if (static_cast<Eigen::Index>(sensors.size()) != n ||
      static_cast<Eigen::Index>(actuators.size()) != n)
    throw std::invalid_argument("pi_state_space: need one sensor and one actuator per gain row");
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  plant::lti::StateSpace c;
  c.A = -g.settings.leak_rad_s * I;
  c.B = I;
  c.C = -g.K_I;
  c.D = -g.K_P;
  for (const auto& s : sensors) c.states.push_back("integrator:" + s);
  c.inputs = sensors;
  c.outputs = actuators;
  c.validate();
  return c;
}

std::array<double, 4> closed_loop_mode_polynomial(const PiForceFeedbackSettings& s) {
  const double wd = s.omega_d_rad_s, wl = s.leak_rad_s;
  return {1.0, wl + 2.0 * s.zeta * wd, wd * wd, wd * wd * wl};
}

}  // namespace flexloop::controller::design
