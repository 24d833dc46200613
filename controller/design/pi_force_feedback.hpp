// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Integral force feedback with a proportional part (doc/design.md §4, seed slide 31), designed from
// the linearised model of a suspension whose dynamic coordinates are the strut elongations and
// whose sensors measure the strut forces sigma_1 = sigma_a + S e (+ S_d e'):
//
//   sigma_a(s) = C(s) sigma_1(s),     C(s) = -(K_P + K_I / (s + w_l)),
//   K_P = (w_d^2 I)^-1 Mdd^-1 Kdd - I,     K_I = 2 zeta w_d (I + K_P),
//
// w_l = 0 is the pure integrator of the seed; w_l > 0 is the "leaky" integrator (a first-order
// low-pass) that gives the loop static stiffness back.
//
// Why it works: with Mdd e'' + sigma_1 = (floor terms) and Kdd = k I (equal struts), the loop
// gives Mdd s^2 e + (I + C')^-1 Kdd e = 0 with I + C' = (I + K_P)(s + w_l + 2 zeta w_d)/(s + w_l)
// and (I + K_P)^-1 Kdd = w_d^2 Mdd, so every mode obeys the same scalar equation
//   s^2 (s + w_l + 2 zeta w_d) + w_d^2 (s + w_l) = 0,
// i.e. s (s^2 + 2 zeta w_d s + w_d^2) = 0 for w_l = 0: six pole pairs at w_d with damping zeta
// and six poles at s = 0. `closed_loop_mode_polynomial` returns that cubic.
//
// The controller as a state space (for the closed loop and for the runtime):
//   xi' = -w_l xi + sigma_1,   sigma_a = -(K_P sigma_1 + K_I xi).
// Its zero-order-hold discretisation (a = e^{-w_l T}, b = (1 - a)/w_l, b = T for w_l = 0),
// closed around the sensors' feedthrough of the controller's own command, is what
// controller/runtime/pi_controller.hpp runs (see there and plant/lti/feedback_interconnection).
//
// Per strut (any number of struts, decentralised: Preumont's integral force feedback, one loop
// per collocated actuator and force sensor). The rule above needs the struts to be the dynamic
// coordinates; per strut it keeps the one-strut case of it. Strut i, of axial stiffness k_i,
// pushes through b_i (its stress's generalised force is -b_i sigma_a) on the mass
//   m_i = 1 / (b_i^T Mdd^-1 b_i),   1/m_i = -lim_{s->inf} s^2 e_i(s) / sigma_a_i(s)
// (the mass its own force accelerates, the others held by nothing), and its loop is tuned as
// the seed's one-strut machine k_i, m_i would be, to w_d with damping zeta:
//   K_P,i = k_i / (m_i w_d^2) - 1,     K_I,i = 2 zeta w_d (1 + K_P,i),
// K_P and K_I diagonal. Where the struts are the dynamic coordinates (b_i = unit vectors) this
// is the diagonal of the coupled K_P above. With equal struts (equal k_i / m_i) and the struts
// the only stiffness, every mode j of the passive machine (w_j) obeys
//   s^2 (1 + K_P)(s + w_l + 2 zeta w_d) + w_j^2 (s + w_l) = 0,
// the cubic above for the mode whose w_j^2 = k/m: the loops soften every strut by 1 + K_P and
// damp every mode, those below sqrt(k/m) more than zeta, those above less.
#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::controller::design {

struct PiForceFeedbackSettings {
  double omega_d_rad_s;   ///< target frequency of every closed-loop mode, > 0
  double zeta;            ///< target damping ratio, > 0
  double leak_rad_s = 0;  ///< 0: pure integrator; > 0: leaky integrator corner
};

struct PiGains {
  Eigen::MatrixXd K_P, K_I;  ///< n x n, acting on the strut-force vector
  PiForceFeedbackSettings settings;
};

/// The gains of the seed's formula from the dynamic-coordinate blocks of the linearised mass and
/// stiffness matrices. @throws std::invalid_argument for non-square or mismatched matrices, a
/// singular Mdd or non-positive settings.
PiGains design_pi_force_feedback(const Eigen::MatrixXd& Mdd, const Eigen::MatrixXd& Kdd,
                                 const PiForceFeedbackSettings& settings);

/// One collocated pair (an actuator stress and the force sensor of the same strut): the strut's
/// axial stiffness k_i (its sensor reads sigma_1 = sigma_a + k_i e_i + d_i e_i') and 1/m_i, the
/// inverse of the mass its own force accelerates (header comment).
struct CollocatedStrut {
  double stiffness = 0;     ///< k_i > 0
  double inverse_mass = 0;  ///< 1/m_i > 0
};

/// The per-strut gains (header comment): diagonal K_P, K_I, one entry per strut in its order.
/// @throws std::invalid_argument for no struts, a k_i or 1/m_i not finite and positive, or
/// non-positive settings.
PiGains design_pi_force_feedback_per_strut(const std::vector<CollocatedStrut>& struts,
                                           const PiForceFeedbackSettings& settings);

/// The controller as a labelled state space: inputs the sensor names, outputs the actuator names,
/// states "integrator:<sensor>".
plant::lti::StateSpace pi_state_space(const PiGains& gains, const std::vector<std::string>& sensors,
                                      const std::vector<std::string>& actuators);

/// Coefficients of the closed-loop polynomial of every mode (equal struts, no preload, no
/// passive damping), highest power first: s^3 + (w_l + 2 zeta w_d) s^2 + w_d^2 s + w_d^2 w_l.
std::array<double, 4> closed_loop_mode_polynomial(const PiForceFeedbackSettings& settings);

}  // namespace flexloop::controller::design
