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
  std::string place;  ///< "file:line" of leak_hz (or of the table), for messages about the loop
};

struct DiscretisationSettings {
  plant::lti::DiscretisationMethod method = plant::lti::DiscretisationMethod::kZeroOrderHold;
  double rate_hz = 10000.0;
  double prewarp_hz = 0.0;
};

/// Stationary random floor acceleration on every disturbance input.
struct FloorSettings {
  std::string spectrum = "white";  ///< "white" (band-limited by the sample rate) or "VC-A".."VC-E"
  double rms_mps2 = 1e-3;          ///< white only: per channel
  std::uint64_t seed = 1;
};

/// Piezo actuator: command -> force with gain, saturation and an optional first-order lag.
struct ActuatorEffect {
  bool present = false;
  double gain = 1.0;
  double force_limit_n = 0;  ///< |force| <= limit
  double lag_s = 0;          ///< time constant; 0: no lag
};

/// A sensor: gain error, white noise, ADC (bits over a full-scale range), delay in samples.
struct SensorEffect {
  bool present = false;
  double gain_error = 0;
  double noise_rms = 0;  ///< SI units of the signal
  int adc_bits = 16;
  double adc_range = 0;  ///< full-scale range (span), SI
  int delay_samples = 0;
  std::uint64_t seed = 2;
};

/// The simulated hardware; every effect is off unless its table is present.
struct EffectsSettings {
  ActuatorEffect actuator;
  SensorEffect force_sensor, accelerometer;
  int transport_delay_samples = 0;  ///< plant -> controller, in samples; 0: none
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
  EffectsSettings effects;
  RunSettings run;
};

Scene load_scene(const std::string& path);
Scene parse_scene(const std::string& toml_text, const std::string& file_name);

/// True when the TOML file has a [scene] table (so a command can take a model or a scene).
bool is_scene_file(const std::string& path);

}  // namespace flexloop::scene
