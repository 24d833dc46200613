#pragma once
// A scene file (TOML) says what to run: which model, which of its inputs are disturbances and
// actuators and which outputs are performance signals and sensors, the controller, the
// discretisation, the floor excitation and the run settings. Format in README.md "Scene files".
// Bad input throws flexloop::InputError "file:line: [table]: what is wrong"; nothing is read
// beyond the first problem.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "plant/lti/discretise.hpp"

namespace flexloop::scene {

struct ControllerSettings {
  bool enabled = true;
  double omega_d_hz = 10.0;  ///< closed-loop mode frequency of the PI force feedback
  double zeta = 0.5;         ///< closed-loop damping ratio
  double leak_hz = 0.0;      ///< 0: pure integrator
  double force_limit_n = std::numeric_limits<double>::infinity();  ///< actuator saturation
};

struct DiscretisationSettings {
  plant::lti::DiscretisationMethod method = plant::lti::DiscretisationMethod::kZeroOrderHold;
  double rate_hz = 10000.0;
  double prewarp_hz = 0.0;
};

/// Stationary random floor acceleration on every disturbance input.
struct FloorSettings {
  std::string spectrum = "white";  ///< "white": band-limited by the sample rate
  double rms_mps2 = 1e-3;          ///< per channel
  std::uint64_t seed = 1;
};

struct RunSettings {
  double duration_s = 10.0;
};

struct Scene {
  std::string file;  ///< as given
  std::string name;
  std::string model_path;  ///< resolved relative to the scene file's folder
  bool gravity_preload = false;
  std::vector<std::string> disturbances, actuators, performance, sensors;
  ControllerSettings controller;
  DiscretisationSettings discretisation;
  FloorSettings floor;
  RunSettings run;
};

Scene load_scene(const std::string& path);
Scene parse_scene(const std::string& toml_text, const std::string& file_name);

/// True when the TOML file has a [scene] table (so a command can take a model or a scene).
bool is_scene_file(const std::string& path);

}  // namespace flexloop::scene
