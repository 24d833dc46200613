// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Part of the loop artefact's schema: the discrete PI force feedback's start-up parameters, as the
// offline design gives them (controller/design: PiGains), for the compiled and the general
// controller alike (controller/runtime).
#include <Eigen/Core>

namespace flexloop::artefact {

struct PiParameters {
  Eigen::MatrixXd K_P, K_I;  ///< N x N, full (coupled) gains
  double dt = 0;             ///< sample time [s], > 0
  double leak_rad_s = 0;     ///< w_l >= 0; 0: pure integrator
  /// Actuator limits [N]: empty (none), one value for every channel, or N values.
  Eigen::VectorXd u_min, u_max;
  /// D22, the sensors' feedthrough from the command: empty means the identity.
  Eigen::MatrixXd feedthrough;
  /// Samples between a command and the measurement that first contains it, beyond the one
  /// sample of the loop itself (sensor delay + transport delay); 0 .. kMaxFeedthroughDelay.
  int feedthrough_delay = 0;
};

/// The longest sensor + transport delay the feedthrough removal can follow.
inline constexpr int kMaxFeedthroughDelay = 32;

}  // namespace flexloop::artefact
