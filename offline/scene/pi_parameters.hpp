// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Start-up parameters of the runtime PI controller (controller/runtime/pi_controller.hpp) from a
// scene's design: the designed gains and leak at the loop's sample time, and the scene's
// [controller] force limit (for the anti-windup) when it sets one. Loops that simulate hardware
// effects add what those imply (loop_artefact_builder.hpp: pi_parameters_with_hardware).
#include <cmath>

#include "controller/runtime/pi_controller.hpp"
#include "offline/scene/scene_plant.hpp"

namespace flexloop::scene {

inline artefact::PiParameters pi_parameters(const ScenePlant& p, double dt) {
  artefact::PiParameters pi;
  pi.K_P = p.gains.K_P;
  pi.K_I = p.gains.K_I;
  pi.dt = dt;
  pi.leak_rad_s = p.gains.settings.leak_rad_s;
  const double limit = p.scene.controller.force_limit_n;
  if (std::isfinite(limit)) {
    pi.u_min = Eigen::VectorXd::Constant(1, -limit);
    pi.u_max = Eigen::VectorXd::Constant(1, limit);
  }
  return pi;
}

}  // namespace flexloop::scene
