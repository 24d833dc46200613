// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Is the SAMPLED force-feedback loop stable? (doc/design.md §5, §6; issue 17, case 7)
//
// loop_stability.hpp judges the continuous loop. The loop that runs is sampled: the feedback
// path G22 (actuators -> force sensors, floor held still) discretised at the loop's rate with the
// scene's method, the discrete PI of controller/runtime/pi_controller.hpp, the command held over
// each sample, and what the simulated hardware puts in between, as far as it is linear (noise,
// ADC and saturation are not: they change no pole). A continuous loop that is stable can be
// unstable sampled: a one-strut loop placed at w_d = 100 Hz and sampled at 200 Hz grows by a
// factor of several per sample. This builds the loop's one-step matrix and judges its eigenvalues.
//
// The runtime loop at sample k (plant/runtime/simulated_hardware.hpp, pi_controller.hpp), floor
// still, with m channels, d = sensor delay + transport delay [samples]:
//   s_k  = Cd x_k + Dd h_k                       sensor signal; h_k = force held since k-1
//   y_k  = (1 + eps) s_{k-d}                     what the controller receives (gain error eps)
//   f_k  = y_k - F u_{k-1-d}                     the controller removes its own force (F = D22
//                                                as the runtime knows it: the identity by default)
//   u_k  = G_f f_k + G_x xi_k,   G_f = -E K_P,  G_x = -E K_I,  E = (I + K_P F)^-1
//   xi_{k+1} = a xi_k + b (f_k + F u_k),   a = e^{-w_l T},  b = (1 - a)/w_l  (T when w_l = 0)
//   actuator: c_k = g u_k; without a lag the force is c_k; with a lag tau (first_order_lag.hpp)
//             the sample's mean force (1 - b_l) c_k + b_l l_k,  l_{k+1} = (1 - a_l) c_k + a_l l_k,
//             a_l = e^{-T/tau},  b_l = (tau/T)(1 - a_l)
//   x_{k+1} = Ad x_k + Bd force_k,   h_{k+1} = force_k.
// States of the loop: [x; h; s_{k-1} .. s_{k-d}; u_{k-1} .. u_{k-1-d}; xi; l (with a lag)]. With
// d = 0, eps = 0, g = 1, no lag and F = Dd it is plant::lti::close_loop_sampled's loop (whose
// held-command state is h here).
//
// The verdict is the continuous one's (loop_stability.hpp) mapped by z = e^{sT}: a pole counts as
// unstable when |z| > e^{kUnstableTolerance w_d T}, but never within kSampledRoundingTolerance of
// the unit circle. The pure integrator's poles (w_l = 0) sit at z = 1, marginal and not unstable,
// as they sit at s = 0 in the continuous loop. The eigenvalues are computed after exact
// power-of-two balancing (states in metres beside states in newtons); the metrology frame's
// six-fold pole at z = 1 then comes out within 3e-14 of the circle from 100 Hz to 1 MHz, where
// the mapped tolerance is 6e-9 .. 6e-13 (without balancing: 2e-7 at 10 kHz).
#include <Eigen/Dense>

#include "controller/design/pi_force_feedback.hpp"
#include "plant/lti/discretise.hpp"

namespace flexloop::controller::design {

/// The linear part of what lies between the controller and the plant in the runtime loop.
struct SampledLoopHardware {
  int feedthrough_delay = 0;     ///< d: force-sensor delay + transport delay [samples], >= 0
  double actuator_gain = 1.0;    ///< g: force per command unit, != 0
  double actuator_lag_s = 0;     ///< tau [s]; 0: no lag
  double sensor_gain_error = 0;  ///< eps of the force sensors, > -1
  /// F, the sensors' feedthrough of the command as the controller removes it (PiParameters::
  /// feedthrough; StateSpaceParameters::feedthrough); empty: the identity, as the runtime PI
  /// takes it.
  Eigen::MatrixXd removed_feedthrough;
};

/// |z| - 1 below this is rounding, whatever the rate: 1e-12 per sample is a growth of 1e-6 / s
/// at 1 MHz (the mapped tolerance there is 6e-13 for w_d = 2 pi x 10 Hz).
inline constexpr double kSampledRoundingTolerance = 1e-12;

struct SampledLoopStability {
  Eigen::VectorXcd poles;           ///< eigenvalues of the loop's one-step matrix (z-plane)
  double spectral_radius = 0;       ///< max |z|
  double tolerance = 0;             ///< |z| above 1 + this counts as unstable
  int unstable = 0;                 ///< poles with |z| > 1 + tolerance
  int marginal = 0;                 ///< poles within the tolerance of the unit circle
  double largest_inner_radius = 0;  ///< max |z| of the poles inside the circle (not marginal)
  bool stable() const { return unstable == 0; }
};

/// The loop's one-step matrix (states as in the header comment). g22: the feedback path
/// (actuators -> sensors, floor held still) discretised at the loop's sample time; as many
/// inputs and outputs as the gains have rows. @throws std::invalid_argument for mismatched
/// sizes, a negative delay, a zero actuator gain, eps <= -1, a negative lag, or I + K_P F
/// singular (ill-posed loop).
Eigen::MatrixXd sampled_loop_matrix(const plant::lti::DiscreteStateSpace& g22, const PiGains& gains,
                                    const SampledLoopHardware& hardware);

/// Poles and verdict of the sampled loop. Same exceptions; std::runtime_error when the
/// eigenvalues do not converge.
SampledLoopStability sampled_loop_stability(const plant::lti::DiscreteStateSpace& g22,
                                            const PiGains& gains,
                                            const SampledLoopHardware& hardware);

/// Any discrete controller x+ = Ac x + Bc y, u = Cc x + Dc y (ns sensors in, nc actuators out) as
/// the runtime runs it (controller/runtime/state_space_controller.hpp): with m = nc actuators and
/// ns sensors the loop is the one above with u_k = E (Cc xc_k + Dc f_k), E = (I - Dc F)^-1,
/// xc_{k+1} = Ac xc_k + Bc (f_k + F u_k), and xc in place of xi. The PI is the controller
/// Ac = a I, Bc = b I, Cc = -K_I, Dc = -K_P (pi_discrete_controller). F (removed_feedthrough)
/// is ns x nc; empty means the identity (ns = nc). @throws std::invalid_argument for mismatched
/// sizes or sample times, the hardware's refusals above, or I - Dc F singular.
Eigen::MatrixXd sampled_loop_matrix(const plant::lti::DiscreteStateSpace& g22,
                                    const plant::lti::DiscreteStateSpace& controller,
                                    const SampledLoopHardware& hardware);

/// The same loop with an input at the actuators: the one-step matrix A, where a perturbation e_k
/// added to the command on its way to the actuators enters (u_k + e_k is what they get; the
/// controller still removes and integrates its own u_k), and the command u_k read from the loop
/// state. The transfer H(z) = command (zI - A)^-1 perturbation is -T_i of the input
/// complementary sensitivity, S_i = I + H (controller/design/disk_margins.hpp).
struct SampledLoopModel {
  Eigen::MatrixXd A;             ///< n x n
  Eigen::MatrixXd perturbation;  ///< n x nc
  Eigen::MatrixXd command;       ///< nc x n
  double dt = 0;
};
/// Same exceptions as sampled_loop_matrix.
SampledLoopModel sampled_loop_model(const plant::lti::DiscreteStateSpace& g22,
                                    const plant::lti::DiscreteStateSpace& controller,
                                    const SampledLoopHardware& hardware);

/// Poles and verdict with any discrete controller; a pole counts as unstable when |z| >
/// e^{kUnstableTolerance reference_rad_s T} (and never within kSampledRoundingTolerance).
SampledLoopStability sampled_loop_stability(const plant::lti::DiscreteStateSpace& g22,
                                            const plant::lti::DiscreteStateSpace& controller,
                                            const SampledLoopHardware& hardware,
                                            double reference_rad_s);

/// The runtime PI as a discrete controller: Ac = a I, Bc = b I, Cc = -K_I, Dc = -K_P with
/// a = e^{-w_l dt}, b = (1 - a)/w_l (dt when w_l = 0).
plant::lti::DiscreteStateSpace pi_discrete_controller(const PiGains& gains, double dt);

}  // namespace flexloop::controller::design
