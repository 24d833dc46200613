#include "tools/hil/loop_scene.hpp"

#include "plant/model/input_error.hpp"
#include "tools/scene/scene_plant.hpp"
#include "tools/sim/scene_hardware.hpp"

namespace flexloop::hil {

LoopScene load_loop_scene(const std::string& path, double rate_hz) {
  LoopScene s;
  s.scene = scene::load_scene(path);
  if (rate_hz > 0) s.scene.discretisation.rate_hz = rate_hz;
  s.rate_hz = s.scene.discretisation.rate_hz;
  const auto channels = {s.scene.disturbances.size(), s.scene.actuators.size(),
                         s.scene.performance.size(), s.scene.sensors.size()};
  for (const std::size_t n : channels)
    if (n != static_cast<std::size_t>(kChannels))
      throw InputError(s.scene.file,
                       "[plant]: the real-time loop needs 6 disturbances, actuators, performance "
                       "outputs and sensors (the messages' channels)");
  const scene::ScenePlant p = scene::build_scene_plant(s.scene);
  scene::require_stable_loop(p);
  s.plant = scene::sample_scene(p).plant;
  s.controller = sim::pi_parameters_with_hardware(p, s.plant.dt);
  return s;
}

controller::runtime::PiController<double, kChannels> make_loop_controller(const LoopScene& s) {
  return controller::runtime::PiController<double, kChannels>::from_parameters(s.controller);
}

}  // namespace flexloop::hil
