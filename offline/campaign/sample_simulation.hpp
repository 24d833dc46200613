// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A campaign sample's loop as it runs, nonlinear (`--simulate S`, doc/campaign.md "Simulated
// samples"): the sample's loop artefact, built as `flexloop sim` builds a scene's, run by sim's
// own code (online/sim/scene_runs.hpp, in process) for S seconds with the controller on, from
// the loop's stationary start (sim's default), with every effect of the scene: actuator
// saturation and lag, the ADC's rounding and range, sensor noise, delays. The linear figures
// (sample_figures.hpp) count the ADC's rounding as uniform noise and leave saturation out; the
// run does neither. The line's `sim` object:
//   seconds                 S
//   status                  "ran" | "not run: <why>" (the linear loop is not stable, or the
//                           sample was refused) | "error: <what>" (e.g. the run diverged)
//   start                   how the run started (sim's words: "stationary (closed loop)")
//   rms                     {performance channel: RMS over the run} (the true outputs, as sim's)
//   rms_standard_error      {channel: the RMS estimate's standard error by batch means}
//   saturated_share         {actuator: share of samples whose commanded force g u reaches the
//                           actuator's force limit}; null without an actuator effect (no limit)
//   max_abs_command         {actuator: max |u| of the controller's command}
// Figures not computed are null. The noise seeds are a pure function of (plan seed, index): the
// same sample gives the same bytes on any shard, process or engine.
#include <Eigen/Core>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "offline/scene/scene_plant.hpp"

namespace flexloop::campaign {

/// The seeds of a sample's run: its floor (and with it the start's draw), force sensors and
/// accelerometers; each counter_bits(mix(plan seed ^ tag), index, k), a stream apart from the
/// design's.
struct SimulationSeeds {
  std::uint64_t floor = 0, force_sensor = 0, accelerometer = 0;
};
SimulationSeeds simulation_seeds(std::uint64_t plan_seed, long index);

/// Batches of the RMS's standard error (batch means): each S / 20 long.
inline constexpr int kRmsBatches = 20;

/// The `sim` object of a stable sample's loop `p` (sampled: scene::sample_scene(p)), run for
/// `seconds`. Never throws for what the loop does: a run that fails or diverges is "error: ...".
nlohmann::json simulate_sample(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                               double seconds, const SimulationSeeds& seeds);

/// The `sim` object of a sample that is not run (every figure null), status "not run: <why>".
nlohmann::json simulation_not_run(double seconds, const std::string& why);

/// A line without a `sim` object gets the one its status implies: an unstable loop is not run
/// (it diverges), nor a refused or failed sample.
void put_simulation_not_run(nlohmann::json& line, double seconds);

/// The standard error of sqrt(mean(x²)) over `batches` equal batches of x (batch means of x²,
/// by the delta method: SE(mean) / (2 RMS)); NaN for fewer samples than batches or a zero RMS.
double rms_standard_error(const Eigen::Ref<const Eigen::VectorXd>& x, int batches);

}  // namespace flexloop::campaign
