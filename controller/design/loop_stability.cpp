// SPDX-License-Identifier: BSD-3-Clause
#include "controller/design/loop_stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "plant/lti/feedback_interconnection.hpp"
#include "plant/lti/modal_analysis.hpp"

namespace flexloop::controller::design {

namespace {

std::vector<std::string> labels(Eigen::Index n, const char* stem) {
  std::vector<std::string> out;
  for (Eigen::Index i = 0; i < n; ++i) out.push_back(stem + std::to_string(i + 1));
  return out;
}

}  // namespace

LoopStability loop_stability(const plant::lti::StateSpace& g22,
                             const plant::lti::StateSpace& controller, double reference_rad_s) {
  if (g22.nu() != controller.ny() || g22.ny() != controller.nu())
    throw std::invalid_argument(
        "loop_stability: the feedback path has " + std::to_string(g22.nu()) + " inputs and " +
        std::to_string(g22.ny()) + " outputs, the controller " + std::to_string(controller.nu()) +
        " inputs and " + std::to_string(controller.ny()) + " outputs");
  const plant::lti::StateSpace loop = plant::lti::close_loop(g22, controller, {0, 0});
  LoopStability r;
  r.poles = plant::lti::poles(loop);
  const double tolerance = kUnstableTolerance * reference_rad_s;
  r.largest_real_part = r.poles.size() ? r.poles.real().maxCoeff() : 0.0;
  for (const auto& s : r.poles)
    if (s.real() > tolerance) ++r.unstable;
  return r;
}

LoopStability loop_stability(const plant::lti::StateSpace& g22, const PiGains& gains) {
  const Eigen::Index n = gains.K_P.rows();
  if (g22.nu() != n || g22.ny() != n)
    throw std::invalid_argument(
        "loop_stability: the feedback path has " + std::to_string(g22.nu()) + " inputs and " +
        std::to_string(g22.ny()) + " outputs, the controller " + std::to_string(n) + " channels");
  return loop_stability(g22, pi_state_space(gains, labels(n, "sensor "), labels(n, "actuator ")),
                        gains.settings.omega_d_rad_s);
}

std::optional<double> minimum_stable_leak_rad_s(const plant::lti::StateSpace& g22,
                                                const PiGains& gains, double w_max_rad_s,
                                                double rel_tol) {
  if (!(rel_tol > 0) || !(std::isfinite(w_max_rad_s) && w_max_rad_s > 0))
    throw std::invalid_argument(
        "minimum_stable_leak_rad_s: needs rel_tol > 0 and a finite w_max_rad_s > 0");
  const auto stable_with = [&](double leak) {
    PiGains g = gains;
    g.settings.leak_rad_s = leak;
    return loop_stability(g22, g).stable();
  };
  if (stable_with(0.0)) return 0.0;
  if (!stable_with(w_max_rad_s)) return std::nullopt;
  // Unstable at lo, stable at hi; stability is monotone in the leak (see the header).
  double lo = 0.0, hi = w_max_rad_s;
  while (hi - lo > rel_tol * hi) {
    const double mid = 0.5 * (lo + hi);
    (stable_with(mid) ? hi : lo) = mid;
  }
  return hi;
}

Eigen::VectorXd geometric_stiffness_per_mass(const Eigen::MatrixXd& Mdd,
                                             const Eigen::MatrixXd& Gdd) {
  // G v = g M v (Gdd is symmetric at rest; its skew part is dropped): the "natural modes" of the
  // stiffness Gs, whose checks (sizes, finite, Mdd positive definite) apply.
  const Eigen::MatrixXd Gs = 0.5 * (Gdd + Gdd.transpose());
  return plant::lti::natural_modes(Mdd, Gs).omega_squared.real();
}

double equal_strut_minimum_leak_rad_s(const Eigen::MatrixXd& Mdd, const Eigen::MatrixXd& Gdd,
                                      const PiForceFeedbackSettings& s) {
  const double wd = s.omega_d_rad_s;
  double bound = 0;
  for (double g : geometric_stiffness_per_mass(Mdd, Gdd)) {
    // a1 = w_d^2 + g_i <= 0: the cubic is unstable whatever the leak.
    if (wd * wd + g <= 0) return std::numeric_limits<double>::infinity();
    if (g < 0) bound = std::max(bound, 2 * s.zeta * wd * (-g) / (wd * wd + g));
  }
  return bound;
}

}  // namespace flexloop::controller::design
