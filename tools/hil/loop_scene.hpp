#pragma once
// What the plant and controller processes need from a scene, computed once at start-up (the
// offline pipeline of tools/scene/scene_plant.hpp): the scene (floor and effects, composed by the
// plant process), the plant sampled at the loop's rate (the scene's [discretisation] rate unless
// overridden), and the PI controller's parameters at that rate with what the hardware effects
// imply (actuator limit for the anti-windup, sensor + transport delay of its own force). The
// loop's messages carry 6 + 6 channels, so the scene must have 6 disturbances, 6 actuators, 6
// performance outputs and 6 sensors, and its closed loop must be stable.
// Errors: flexloop::InputError naming the scene file.
#include <string>

#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/discretise.hpp"
#include "tools/hil/plant_station.hpp"
#include "tools/scene/scene.hpp"

namespace flexloop::hil {

struct LoopScene {
  scene::Scene scene;
  double rate_hz = 0;
  plant::lti::DiscreteStateSpace plant;
  controller::runtime::PiParameters controller;  ///< dt = 1 / rate_hz
};

/// Loads and samples `path` at rate_hz (<= 0: the scene's rate).
LoopScene load_loop_scene(const std::string& path, double rate_hz);

/// The loop's controller (PiController<double, 6>).
controller::runtime::PiController<double, kChannels> make_loop_controller(const LoopScene& s);

}  // namespace flexloop::hil
