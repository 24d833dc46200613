// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The reference scene for runtime tests and benchmarks: the metrology frame under PI force
// feedback (tools/scenes/metrology_frame.toml), built once per process, with its ZOH plant at
// 10 kHz and the offline model of the sampled closed loop.
#include <filesystem>
#include <string>

#include "controller/runtime/pi_controller.hpp"
#include "offline/scene/pi_parameters.hpp"
#include "offline/scene/scene_plant.hpp"

namespace flexloop::test {

struct Metrology {
  scene::ScenePlant p;
  scene::SampledScene s;
};

/// The scene path from the repository root (tests run there), else found from this file's path
/// (benchmarks may run anywhere).
inline std::string metrology_scene_path() {
  const std::string rel = "tools/scenes/metrology_frame.toml";
  if (std::filesystem::exists(rel)) return rel;
  return (std::filesystem::path(__FILE__).parent_path() / "../.." / rel).string();
}

inline const Metrology& metrology() {
  static const Metrology m = [] {
    Metrology r{scene::build_scene_plant(scene::load_scene(metrology_scene_path())), {}};
    r.s = scene::sample_scene(r.p);
    return r;
  }();
  return m;
}

/// The designed gains at the scene's sample time (the scene sets no controller force limit).
inline artefact::PiParameters metrology_pi_parameters() {
  return scene::pi_parameters(metrology().p, metrology().s.plant.dt);
}

}  // namespace flexloop::test
