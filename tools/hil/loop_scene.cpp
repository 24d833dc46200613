#include "tools/hil/loop_scene.hpp"

#include <cmath>

#include "tools/scene/scene_plant.hpp"

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
  s.plant = scene::sample_scene(p).plant;
  auto& c = s.controller;
  c.K_P = p.gains.K_P;
  c.K_I = p.gains.K_I;
  c.dt = s.plant.dt;
  c.leak_rad_s = p.gains.settings.leak_rad_s;
  if (std::isfinite(s.scene.controller.force_limit_n)) {
    c.u_min = Eigen::VectorXd::Constant(1, -s.scene.controller.force_limit_n);
    c.u_max = Eigen::VectorXd::Constant(1, s.scene.controller.force_limit_n);
  }
  return s;
}

controller::runtime::PiController<double, kChannels> make_loop_controller(const LoopScene& s) {
  return controller::runtime::PiController<double, kChannels>::from_parameters(s.controller);
}

}  // namespace flexloop::hil
