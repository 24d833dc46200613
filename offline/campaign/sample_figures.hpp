// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One sample of a campaign (issue 47, item 3; doc/campaign.md): a machine -- the scene and the FE
// model with the drawn parameters -- re-linearised from the model, discretised at the scene's
// rate and method, closed with the campaign's controller and judged as the loop runs, with the
// same figure functions `flexloop analyse` prints (offline/pipeline/loop_figures.hpp):
//   status                  "stable" | "unstable" (analyse's verdict: the continuous loop, where
//                           there is one, and the sampled loop as it runs) | "marginal: <why>"
//                           (judged stable, but its closed loop has no stationary state: no
//                           RMS, though margins and sigma are computed) | "refused: <why>" (a
//                           statically unstable machine: buckling under preload; a refused
//                           discretisation) | "error: <what>" (anything unexpected)
//   spectral_radius         of the sampled loop (scene::sampled_loop)
//   largest_inner_radius    the largest |z| of its poles inside the unit circle, those on it left
//                           out (the PI integrator's at z = 1, which make every stable PI
//                           machine's spectral radius 1): how far a stable loop is from the
//                           circle (subset simulation's margin, subset_campaign.hpp)
//   natural_frequencies_hz  the passive machine's, ascending
//   rms, rms_open           {performance channel: stationary RMS}, closed and open loop, exact by
//                           the discrete Lyapunov equation with every noise source of the scene
//                           (floor filter, sensor noise, the ADC's rounding as LSB²/12)
//   disk_margin_db/_deg     loop at a time, the worst loop: 20 log10 of the balanced disk's upper
//                           gain factor ("+inf" when unbounded: a disk of size >= 2) and its phase
//   disk_margin_all_db/_deg every loop at once
//   sigma_max, peak_sigma   the closed loop floor -> performance's largest singular value on the
//                           settings' grid (analyse's closed loop: continuous where the loop has a
//                           continuous form, else sampled) and its maximum
//   sim                     with --simulate S only: the loop run for S s by `flexloop sim`'s code,
//                           with the nonlinear effects (offline/campaign/sample_simulation.hpp)
// A figure not computed is null (refused, error; an unstable loop has no RMS, margins or sigma).
// The controller: frozen, the nominal machine's PI gains on every machine (one controller for the
// fleet); redesigned, the PI designed on each machine's own plant (a commissioning step). A
// state-space controller is a fixed file: the same in both. A controller FMU cannot be seen into:
// refused at construction.
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "controller/design/pi_force_feedback.hpp"
#include "offline/campaign/sample_simulation.hpp"
#include "offline/scene/scene.hpp"
#include "plant/model/model.hpp"

namespace flexloop::campaign {

enum class ControllerMode { kFrozen, kRedesigned };

struct SampleSettings {
  ControllerMode mode = ControllerMode::kFrozen;
  std::vector<double> sigma_grid_hz;  ///< where sigma_max is evaluated (empty: no sigma figures)
  /// > 0: each sample given its seeds also runs its loop for this long (sample_simulation.hpp)
  double simulate_s = 0;
};

/// Built once from the nominal scene: designs the nominal controller (frozen) and holds it.
class SampleEvaluator {
 public:
  /// @throws flexloop::InputError naming the scene for a controller FMU, a nominal machine that
  /// is statically unstable, or a nominal scene the pipeline refuses. A scene without a
  /// controller ([controller] type = "none") makes an open-loop campaign (open_loop()).
  SampleEvaluator(const scene::Scene& nominal_scene, const plant::model::Model& nominal_model,
                  SampleSettings settings);
  /// One machine: its scene and its model (both already carrying the drawn values). Returns the
  /// JSONL fields above. Never throws for what the machine is; an unexpected failure is status
  /// "error: <what>". With settings' simulate_s > 0 and `seeds`, also the `sim` object of
  /// offline/campaign/sample_simulation.hpp (its run for a stable loop, "not run" otherwise).
  nlohmann::json evaluate(const scene::Scene& scene, const plant::model::Model& model,
                          const std::optional<SimulationSeeds>& seeds = std::nullopt) const;
  const nlohmann::json& nominal() const { return nominal_; }
  bool open_loop() const { return open_loop_; }

 private:
  // The figures, and the run when `seeds` are given, of a machine.
  nlohmann::json machine_figures(const scene::Scene& scene, const plant::model::Model& model,
                                 const std::optional<SimulationSeeds>& seeds) const;

  SampleSettings settings_;
  controller::design::PiGains nominal_gains_;  ///< the nominal machine's (PI scenes)
  bool pi_ = false;
  bool open_loop_ = false;  ///< the scene has no controller: the passive machine is judged
  nlohmann::json nominal_;
};

}  // namespace flexloop::campaign
