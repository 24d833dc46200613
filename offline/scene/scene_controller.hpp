// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A scene's state-space controller ([controller] type = "state_space"): the file `file` names,
// in flexloop's own state-space layout (plant/lti/state_space_json.hpp), either
//   continuous: {"states", "inputs", "outputs", "A", "B", "C", "D"}  (flexloop linearise's form),
//               discretised here at the scene's rate with the scene's method; or
//   discrete:   {"method", "dt", "prewarp_hz", "spectral_radius", "states", "inputs", "outputs",
//                "Ad", "Bd", "Cd", "Dd"}  (flexloop discretise's form), designed at the scene's
//               sample time (dt = 1 / rate_hz).
// The controller's inputs are the scene's sensors and its outputs the scene's actuators, by name,
// in any order (they are put into the scene's order here). The sign convention is the seed's:
// u = C x + D y is the command itself (negative feedback is in the matrices, as in the PI's
// Dc = -K_P). Bad input: flexloop::InputError naming the controller file and key.
#include <optional>

#include "offline/scene/scene.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::scene {

struct SceneController {
  std::optional<plant::lti::StateSpace> continuous;  ///< when the file is continuous
  plant::lti::DiscreteStateSpace discrete;           ///< at the scene's rate, scene channel order
};

SceneController load_scene_controller(const Scene& scene);

}  // namespace flexloop::scene
