#pragma once
// What the plant and controller processes need from a scene, computed once at start-up (the
// offline pipeline of tools/scene/scene_plant.hpp): the plant and the PI controller sampled at the
// loop's rate (the scene's [discretisation] rate unless overridden), the floor's RMS and seed,
// and the actuator limit. The loop's messages carry 6 + 6 channels, so the scene must have 6
// disturbances, 6 actuators, 6 performance outputs and 6 sensors; with_loop_plant() hands the
// matching compiled DensePlant<double, NX, 12, 12> to a callback (plant/runtime/runtime_sizes.hpp).
// Errors: flexloop::InputError naming the scene file.
#include <string>
#include <type_traits>

#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/model/input_error.hpp"
#include "plant/runtime/runtime_sizes.hpp"
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

/// Calls f(DensePlant<double, NX, 12, 12>) for the compiled NX of the sampled plant and returns
/// what f returns.
template <class F>
decltype(auto) with_loop_plant(const LoopScene& s, F&& f) {
  const auto& d = s.plant.sys;
  using Result = std::invoke_result_t<F, plant::runtime::DensePlant<double, 12, 12, 12>>;
  return plant::runtime::with_runtime_size(d.nx(), d.nu(), d.ny(), [&](auto size) -> Result {
    using Size = decltype(size);
    if constexpr (Size::NU == 2 * kChannels && Size::NY == 2 * kChannels) {
      return f(plant::runtime::DensePlant<double, Size::NX, Size::NU, Size::NY>::from_matrices(
          d.A, d.B, d.C, d.D));
    } else {
      throw InputError(s.scene.file,
                       "[plant]: the real-time loop needs 6 + 6 inputs and 6 + 6 "
                       "outputs (the messages' channels)");
    }
  });
}

}  // namespace flexloop::hil
