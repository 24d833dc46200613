// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The offline half of a scene: model -> (static equilibrium under gravity when the scene asks
// for the preload) -> linearisation -> generalised plant G with inputs [disturbances;
// actuators] and outputs [performance; sensors] -> PI force-feedback design (coupled from Mdd,
// Kdd, or per collocated strut: collocated_struts.hpp) -> continuous closed loop; and the sampled
// versions at the scene's rate (plant and controller discretised with the scene's method, closed
// as the simulation loop closes them).
#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "controller/design/loop_stability.hpp"
#include "controller/design/pi_force_feedback.hpp"
#include "controller/design/sampled_loop_stability.hpp"
#include "offline/scene/scene.hpp"
#include "offline/scene/scene_controller.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/feedback_interconnection.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model.hpp"

namespace flexloop::scene {

struct ScenePlant {
  Scene scene;
  plant::model::Model model;
  plant::model::Linearisation lin;
  int equilibrium_iterations = 0;          ///< Newton steps to the gravity-loaded equilibrium
  Eigen::VectorXd natural_frequencies_hz;  ///< undamped, about the operating point
  plant::lti::StaticStability statics;     ///< of those modes; the buckling multiplier of the load
  plant::lti::StateSpace plant;            ///< G: [w; u] -> [z; y]
  plant::lti::LoopPartition partition;     ///< sizes of w and z
  controller::design::PiGains gains;       ///< the PI's (type "pi_force_feedback")
  /// The PI's struts when it is designed per strut (collocated_struts.hpp); empty: the coupled
  /// rule of the struts that are the dynamic coordinates.
  std::vector<controller::design::CollocatedStrut> struts;
  /// type "state_space": the user's controller, discrete at the scene's rate (and continuous when
  /// the file is)
  std::optional<SceneController> state_space;
  plant::lti::StateSpace controller;   ///< y -> u, continuous (the PI; a continuous state space)
  plant::lti::StateSpace closed_loop;  ///< w -> z (T)
  /// The feedback path G22 (actuators -> sensors, floor held still) and the poles of the loop it
  /// makes with the controller: the closed loop's poles without the floor's integrator states.
  plant::lti::StateSpace feedback_path;
  controller::design::LoopStability loop;
};

/// True for a controller FMU ([controller] type = "fmu"): the loop runs it (controller/fmu), the
/// offline side cannot see into it.
inline bool has_fmu_controller(const ScenePlant& p) {
  return p.scene.controller.type == "fmu";
}

/// False for a scene with [controller] type = "none": no design, no closed loop; the sampled
/// scene then has the plant alone. False for a controller FMU too: the offline side cannot see
/// into it (no matrices, no poles), so its analyses are the plant's alone and say so.
inline bool has_controller(const ScenePlant& p) {
  return p.scene.controller.type != "none" && !has_fmu_controller(p);
}

/// True for the PI force feedback (type "pi_force_feedback"), whose design, leak and remedies
/// apply.
inline bool has_pi_controller(const ScenePlant& p) {
  return p.scene.controller.type == "pi_force_feedback";
}

/// True when the loop has a continuous form: the PI, or a state-space controller given in
/// continuous time (closed_loop and loop are then filled).
inline bool has_continuous_loop(const ScenePlant& p) {
  return has_pi_controller(p) || (p.state_space && p.state_space->continuous);
}

/// The rate a state-space controller's loop is judged against: a pole counts as unstable when it
/// grows faster than kUnstableTolerance x this (the Nyquist frequency, rad/s; the PI's is w_d).
double state_space_reference_rad_s(const Scene& scene);

/// The smallest stable leak [Hz] of the scene's loop (0: stable without one; nullopt: none up to
/// the scene's omega_d). controller/design/loop_stability.hpp explains when one is needed.
std::optional<double> minimum_stable_leak_hz(const ScenePlant& p);

/// The loop as it runs (controller/design/sampled_loop_stability.hpp): the feedback path G22
/// discretised at a rate with the scene's method, the runtime PI with `gains`, the held command,
/// and the linear part of the scene's [effects] (force-sensor + transport delay, actuator gain and
/// lag, force-sensor gain error).
struct SampledLoop {
  double rate_hz = 0;
  plant::lti::DiscretisationMethod method = plant::lti::DiscretisationMethod::kZeroOrderHold;
  controller::design::SampledLoopHardware hardware;
  controller::design::SampledLoopStability stability;
};

/// At the scene's rate with its designed gains.
/// @throws flexloop::InputError naming the scene file when the discretisation is refused.
SampledLoop sampled_loop(const ScenePlant& p);
/// The loop at the scene's rate with an input at the actuator commands (for its disk margins,
/// controller/design/disk_margins.hpp). Same exception.
controller::design::SampledLoopModel sampled_loop_model(const ScenePlant& p);
/// At another rate and/or with other gains (the searches below).
SampledLoop sampled_loop(const ScenePlant& p, double rate_hz,
                         const controller::design::PiGains& gains);

/// What would make an unstable sampled loop stable, each checked (continuous loop stable too):
/// the lowest rate of the 1-2-5 series above the scene's rate, up to kMaxSuggestedRateHz, and the
/// largest omega_d_hz at the scene's rate (bisection below the scene's, 3 significant digits,
/// rounded down). nullopt: none found.
struct SampledLoopRemedy {
  std::optional<double> rate_hz;
  std::optional<double> omega_d_hz;
};
inline constexpr double kMaxSuggestedRateHz = 1e6;
SampledLoopRemedy stable_sampled_loop_remedy(const ScenePlant& p);

/// For the commands that run the loop (sim, plant, controller, hil), before any run: throws
/// flexloop::InputError
/// - at the scene's [scene] model when the plant itself is statically unstable (p.statics: a
///   preload beyond buckling, named by its buckling multiplier), with or without a controller;
/// - at the scene's [controller] leak_hz (or table) when the continuous loop is unstable, saying
///   how fast it diverges and which leak would make it stable;
/// - at the scene's [discretisation] rate_hz (or table) when the sampled loop (sampled_loop) is
///   unstable, giving its spectral radius and a rate and an omega_d_hz that would be stable
///   (stable_sampled_loop_remedy).
void require_stable_loop(const ScenePlant& p);
/// The second check alone (the sampled loop).
void require_stable_sampled_loop(const ScenePlant& p);

/// Overrides for studies, campaigns and tests: zero every strut damper before linearising; the PI
/// gains given instead of designed on this plant (a campaign's frozen controller: the nominal
/// machine's gains on another machine).
struct ScenePlantOptions {
  bool without_damping = false;
  std::optional<controller::design::PiGains> pi_gains = std::nullopt;
};

/// @throws flexloop::InputError naming the scene (or model) file for bad channels or models.
ScenePlant build_scene_plant(const Scene& scene, const ScenePlantOptions& options = {});
/// The same with the model given (not loaded from scene.model_path: a campaign's machine with its
/// drawn parameters).
ScenePlant build_scene_plant(const Scene& scene, plant::model::Model machine,
                             const ScenePlantOptions& options = {});

/// The scene's [plant] reduction of the linearised plant G (plant/lti/model_reduction.hpp); the
/// floor's position and velocity states, when G has them, stay states with their labels (modal
/// truncation only). @throws flexloop::InputError at the `reduction` key.
plant::lti::StateSpace reduced_plant(const plant::lti::StateSpace& full, const Scene& scene);

struct SampledScene {
  plant::lti::DiscreteStateSpace plant, controller;
  plant::lti::DiscreteStateSpace closed_loop;  ///< w -> z as the simulation loop closes it
};

/// Discretise plant and controller at the scene's rate and method.
/// @throws flexloop::InputError naming the scene file when the discretisation is refused.
SampledScene sample_scene(const ScenePlant& p);

}  // namespace flexloop::scene
