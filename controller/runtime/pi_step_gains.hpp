// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Start-up, shared by the compiled PiController<Scalar, N> and the general GeneralPiController:
// the checked parameters of the discrete PI law (pi_controller.hpp's header comment has the law)
// as n x n matrices in double. One place for the validation and the algebra, so both paths run
// the same controller.
#include <Eigen/Core>
#include <string>

#include "artefact/pi_parameters.hpp"

namespace flexloop::controller::runtime {

struct PiStepGains {
  Eigen::MatrixXd G_f, G_x;  ///< -E K_P, -E K_I with E = (I + K_P D22)^-1
  Eigen::MatrixXd G_x_inv;   ///< G_x^-1 = -K_I^-1 (I + K_P D22): x = G_x^-1 s
  Eigen::MatrixXd D22;       ///< the sensors' feedthrough from the command
  bool identity_feedthrough = true;
  Eigen::VectorXd u_min, u_max;  ///< per channel, ±inf where unlimited
  double a = 1, b = 0;           ///< leak: x+ = a x + b (...)
  int delay = 0;                 ///< feedthrough delay, samples
};

/// @throws std::invalid_argument "<who>: ..." for gains or feedthrough that are not n x n,
/// non-finite numbers, dt <= 0, w_l < 0, limits of the wrong size or with u_min > u_max,
/// I + K_P D22 singular (ill-posed loop), K_I singular (no anti-windup or bumpless start), or a
/// feedthrough delay outside 0 .. kMaxFeedthroughDelay.
PiStepGains pi_step_gains(const artefact::PiParameters& p, Eigen::Index n, const std::string& who);

}  // namespace flexloop::controller::runtime
