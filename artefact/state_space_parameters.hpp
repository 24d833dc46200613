// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Part of the loop artefact's schema: a discrete state-space controller's start-up parameters: the
// user's own design (from MATLAB, Octave, python-control, or flexloop's own discretisation of a
// continuous design), at the loop's sample time, with the loop's actuator limits and the plant's
// feedthrough from command to sensor.
//
//   x_{k+1} = A x_k + B y_k,   u_k = C x_k + D y_k     (y: the sensors, u: the actuator commands)
//
// designed for the discrete plant y_k = C2 x_k + D22 u_k;
// controller/runtime/state_space_controller.hpp says how the runtime realises that against a
// measurement that holds the previous command.
#include <Eigen/Core>
#include <stdexcept>
#include <string>

namespace flexloop::artefact {

/// What the controller does while a command is clamped at an actuator limit.
enum class AntiWindup {
  kNone,  ///< the controller runs on as if unclamped (its state may wind up)
  kHold,  ///< its state holds while any channel is clamped (conditional integration)
};

/// "none", "hold".
inline std::string to_string(AntiWindup a) {
  return a == AntiWindup::kHold ? "hold" : "none";
}
/// @throws std::invalid_argument for another name.
inline AntiWindup parse_anti_windup(const std::string& name) {
  if (name == "hold") return AntiWindup::kHold;
  if (name == "none") return AntiWindup::kNone;
  throw std::invalid_argument("anti-windup \"" + name + "\": expected \"hold\" or \"none\"");
}

struct StateSpaceParameters {
  Eigen::MatrixXd A, B, C, D;  ///< nx x nx, nx x ns, nc x nx, nc x ns
  double dt = 0;               ///< sample time [s], > 0
  /// Actuator limits: empty (none), one value for every channel, or nc values.
  Eigen::VectorXd u_min, u_max;
  /// D22, the sensors' feedthrough from the command (ns x nc); empty: none.
  Eigen::MatrixXd feedthrough;
  /// Samples between a command and the measurement that first contains it, beyond the loop's
  /// own one (sensor + transport delay); 0 .. kMaxFeedthroughDelay (pi_parameters.hpp).
  int feedthrough_delay = 0;
  AntiWindup anti_windup = AntiWindup::kHold;
};

/// The most controller states the runtime takes.
inline constexpr int kMaxControllerStates = 4096;

}  // namespace flexloop::artefact
