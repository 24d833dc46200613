// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Is the force-feedback loop stable, and how much leak does it need? (doc/design.md §4, §9)
//
// The loop is the actuators -> sensors path G22 of the plant with the floor held still, closed by
// the PI controller C(s) = -(K_P + K_I / (s + w_l)). Its poles are the closed loop's poles apart
// from the floor's own integrator states, which the controller cannot move (the full closed loop
// is block-triangular: floor states drive the suspension, nothing drives them).
//
// Why a leak can be necessary. With equal struts (Kdd = k I) the design makes
// (I + K_P)^-1 Kdd = w_d^2 Mdd and I - C(s) = (I + K_P)(s + w_l + 2 zeta w_d) / (s + w_l). With the
// preload's geometric stiffness Gdd and no damping the loop is
//   Mdd s^2 e + (I - C(s))^-1 Kdd e + Gdd e = 0,
// i.e. exactly, per eigenvalue g_i of Mdd^-1 Gdd (real: Mdd > 0, Gdd symmetric):
//   (s^2 + g_i)(s + w_l + 2 zeta w_d) + w_d^2 (s + w_l) = 0.
// For this cubic s^3 + a2 s^2 + a1 s + a0 the Routh conditions reduce to a1 = w_d^2 + g_i > 0 and
// a0 = g_i (w_l + 2 zeta w_d) + w_d^2 w_l > 0 (a2 a1 - a0 = 2 zeta w_d^3 > 0 always). A pure
// integrator (w_l = 0) removes the struts' static stiffness, so any negative g_i (compressed
// struts carrying the weight: the geometric stiffness of an inverted pendulum) gives a real pole
// at about s = -2 zeta g_i / w_d > 0: the frame drifts away. The leak gives static stiffness back;
// the loop is stable iff
//   w_l > w_l,min = max_i 2 zeta w_d (-g_i) / (w_d^2 + g_i)   over g_i < 0.
// Stability is monotone in w_l (a0 grows with it), so minimum_stable_leak finds the exact bound
// of the real model (damped, any struts) by bisection on the loop's poles; the formula above is
// its independent check (tests/controller/test_gravity_preload.cpp).
#include <Eigen/Dense>
#include <optional>

#include "controller/design/pi_force_feedback.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::controller::design {

struct LoopStability {
  Eigen::VectorXcd poles;        ///< of the loop (G22 closed by C), rad/s
  int unstable = 0;              ///< poles with a real part above the tolerance
  double largest_real_part = 0;  ///< rad/s; > 0: the fastest growth rate
  bool stable() const { return unstable == 0; }
};

/// A pole counts as unstable when Re s > kUnstableTolerance * w_d (the pure integrator's poles
/// at s = 0 are marginal, not unstable; rounding puts them within ~1e-12 w_d of 0).
inline constexpr double kUnstableTolerance = 1e-8;

/// Poles of the loop: g22 = actuators -> sensors with the floor held still (as many inputs and
/// outputs as the gains have rows). @throws std::invalid_argument for mismatched sizes or an
/// ill-posed loop (plant::lti::close_loop).
LoopStability loop_stability(const plant::lti::StateSpace& g22, const PiGains& gains);

/// Poles of the loop g22 closed by any controller (sensors in, actuators out; the seed's positive
/// feedback convention, u = C y); a pole counts as unstable when Re s > kUnstableTolerance *
/// reference_rad_s. Same exceptions.
LoopStability loop_stability(const plant::lti::StateSpace& g22,
                             const plant::lti::StateSpace& controller, double reference_rad_s);

/// The smallest leak w_l >= 0 [rad/s] for which the loop is stable: 0 when it is stable without
/// one, nullopt when even w_l = w_max is unstable. Bisection to a relative width rel_tol.
std::optional<double> minimum_stable_leak_rad_s(const plant::lti::StateSpace& g22,
                                                const PiGains& gains, double w_max_rad_s,
                                                double rel_tol = 1e-6);

/// The bound of the header comment for equal undamped struts: max_i 2 zeta w_d (-g_i) /
/// (w_d^2 + g_i) over the negative eigenvalues g_i of Mdd^-1 Gdd (0 when there are none;
/// infinity when some w_d^2 + g_i <= 0: no leak helps then).
double equal_strut_minimum_leak_rad_s(const Eigen::MatrixXd& Mdd, const Eigen::MatrixXd& Gdd,
                                      const PiForceFeedbackSettings& settings);

/// The eigenvalues g_i of Mdd^-1 Gdd, ascending [rad^2/s^2].
Eigen::VectorXd geometric_stiffness_per_mass(const Eigen::MatrixXd& Mdd,
                                             const Eigen::MatrixXd& Gdd);

}  // namespace flexloop::controller::design
