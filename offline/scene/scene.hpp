// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A scene file (TOML) says what to run: which model, which of its inputs are disturbances and
// actuators and which outputs are performance signals and sensors, the controller, the
// discretisation, the floor excitation and the run settings. Format in doc/scene_format.md.
// Bad input throws flexloop::InputError "file:line: [table]: what is wrong"; nothing is read
// beyond the first problem.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "artefact/hardware_settings.hpp"
#include "plant/lti/discretise.hpp"

namespace flexloop::scene {

struct ControllerSettings {
  /// "pi_force_feedback"; "state_space": the user's own design from `file`; "fmu": the user's
  /// controller as an FMI 2.0 Co-Simulation FMU (`file`); or "none": the plant
  /// runs alone (an external controller process, or an open-loop study) and nothing of the PI
  /// applies. enabled = false makes any type "none".
  std::string type = "pi_force_feedback";
  bool enabled = true;
  std::string file;                  ///< state_space: the controller file, resolved like the model
  std::string file_place;            ///< state_space: "file:line" of the `file` key
  std::string anti_windup = "hold";  ///< state_space: "hold" or "none"
  double omega_d_hz = 10.0;          ///< closed-loop mode frequency of the PI force feedback
  double zeta = 0.5;                 ///< closed-loop damping ratio
  double leak_hz = 0.0;              ///< 0: pure integrator
  double force_limit_n = std::numeric_limits<double>::infinity();  ///< actuator saturation
  std::string place;  ///< "file:line" of leak_hz (or of the table), for messages about the loop
  /// fmu (offline/scene/scene_fmu.hpp): `file` is the .fmu (absolute), these its parameters and
  /// the sensors and actuators whose FMU variable has another name (scene channel, FMU variable).
  std::vector<std::pair<std::string, double>> fmu_parameters;
  std::vector<std::pair<std::string, std::string>> fmu_sensor_map, fmu_actuator_map;
  /// fmu: `fmu_max_unpacked_mb`, the cap on the unpacked archive; none: the loader's default.
  std::optional<long> fmu_max_unpacked_mb;
};

/// The highest loop rate a scene (or `build --rate`) may ask for, Hz: the loop commands' --rate
/// ceiling.
inline constexpr double kMaxLoopRateHz = 1e6;

struct DiscretisationSettings {
  plant::lti::DiscretisationMethod method = plant::lti::DiscretisationMethod::kZeroOrderHold;
  double rate_hz = 10000.0;
  double prewarp_hz = 0.0;
};

using artefact::ActuatorEffect;
using artefact::EffectsSettings;
using artefact::FloorSettings;
using artefact::SensorEffect;

struct RunSettings {
  double duration_s = 10.0;
};

/// [plant] reduction: the linearised plant reduced before anything uses it (the loop artefact,
/// sim, hil and analyse then see the reduced one); plant/lti/model_reduction.hpp.
struct ReductionSettings {
  std::string method;   ///< "" (none), "modal", "modal-dc", "balanced"
  int order = 0;        ///< states to keep (0: below_hz says which)
  double below_hz = 0;  ///< modal, modal-dc: keep the modes below this (the rest residualised)
  double band_hz = 0;   ///< modal: judge the modes' contributions up to this (0: everywhere)
  std::string place;    ///< "file:line" of the `reduction` key
};

struct Scene {
  std::string file;  ///< as given
  std::string name;
  std::string model_path;  ///< resolved relative to the scene file's folder
  bool gravity_preload = false;
  std::vector<std::string> disturbances, actuators, performance, sensors;
  ReductionSettings reduction;
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
