// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/sample_simulation.hpp"

#include <cmath>
#include <exception>
#include <limits>

#include "offline/campaign/counter_random.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/runtime/divergence.hpp"

namespace flexloop::campaign {

namespace {

using nlohmann::json;

constexpr std::uint64_t kSimulationTag = 0x73696D2D6E6F6973ull;  // "sim-nois": apart from designs

// Every field of the object, the figures null.
json empty_simulation(double seconds, const std::string& status) {
  return {{"seconds", seconds},
          {"status", status},
          {"start", nullptr},
          {"rms", nullptr},
          {"rms_standard_error", nullptr},
          {"saturated_share", nullptr},
          {"max_abs_command", nullptr}};
}

// {channel name: value} of a per-channel vector; a value that is not finite is null.
json per_channel(const std::vector<artefact::Channel>& channels, const Eigen::VectorXd& v) {
  json j = json::object();
  for (std::size_t i = 0; i < channels.size(); ++i) {
    const double x = v(static_cast<Eigen::Index>(i));
    j[channels[i].name] = std::isfinite(x) ? json(x) : json(nullptr);
  }
  return j;
}

// The sample's artefact as `flexloop sim` builds a scene's (offline/scene/loop_input.cpp: dense
// form, the stationary starts), its duration and seeds the sample's.
artefact::LoopArtefact sample_artefact(const scene::ScenePlant& p,
                                       const scene::SampledScene& sampled, double seconds,
                                       const SimulationSeeds& seeds) {
  artefact::LoopArtefact a = scene::build_loop_artefact(p, sampled, artefact::PlantForm::kDense);
  a.duration_s = seconds;
  a.floor.seed = seeds.floor;
  a.effects.force_sensor.seed = seeds.force_sensor;
  a.effects.accelerometer.seed = seeds.accelerometer;
  return a;
}

// The figures of the commands in the run's log (columns as online/sim/closed_loop_run.hpp):
// max |u| and the share of samples whose commanded force g u reaches the actuator's limit L. A
// controller that clamps its command at L / g (the PI's anti-windup limit) gives g u = L up to
// a rounding: a relative 1e-9 below L counts as at the limit.
void put_command_figures(const artefact::LoopArtefact& a, const sim::RunLog& log, json& j) {
  const Eigen::Index nw = a.disturbances(), nz = a.performance(), ns = a.sensors(),
                     nc = a.actuators();
  const auto commands = log.matrix().middleCols(1 + nw + 2 * nz + ns, nc);
  j["max_abs_command"] =
      per_channel(a.channels.actuators, commands.cwiseAbs().colwise().maxCoeff());
  if (!a.effects.actuator.present) return;
  const auto& e = a.effects.actuator;
  const double at_limit = e.force_limit_n * (1 - 1e-9);
  Eigen::VectorXd share(nc);
  for (Eigen::Index c = 0; c < nc; ++c)
    share(c) = static_cast<double>(((e.gain * commands.col(c)).array().abs() >= at_limit).count()) /
               static_cast<double>(std::max<Eigen::Index>(commands.rows(), 1));
  j["saturated_share"] = per_channel(a.channels.actuators, share);
}

// The run's figures, or its error.
json run_figures(const artefact::LoopArtefact& a, double seconds) {
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(seconds / s.dt);  // as `flexloop sim --duration`
  s.log_every = 1;
  sim::SceneRunOptions o;
  o.start = sim::StartKind::kStationary;
  o.log_on = o.log_off = true;
  o.on_only = true;  // the controller-on run alone; a loop without a controller runs `off` alone
  const sim::BothRuns r = sim::run_artefact(a, s, o);
  const sim::RunResult& run = r.controlled ? r.on : r.off;
  if (run.divergence.happened())
    return empty_simulation(
        seconds, "error: the run " + plant::runtime::describe(run.divergence, a.channels));
  if (!run.controller.failure.empty())
    return empty_simulation(seconds, "error: the controller: " + run.controller.failure);
  json j = empty_simulation(seconds, "ran");
  j["start"] = r.controlled ? r.start_on : r.start_off;
  j["rms"] = per_channel(a.channels.performance, run.rms_performance);
  const Eigen::Index nz = a.performance(), first = 1 + a.disturbances();
  Eigen::VectorXd se(nz);
  for (Eigen::Index i = 0; i < nz; ++i)
    se(i) = rms_standard_error(run.log.matrix().col(first + i), kRmsBatches);
  j["rms_standard_error"] = per_channel(a.channels.performance, se);
  put_command_figures(a, run.log, j);
  return j;
}

}  // namespace

SimulationSeeds simulation_seeds(std::uint64_t plan_seed, long index) {
  const std::uint64_t stream = splitmix64(plan_seed ^ kSimulationTag);
  const auto i = static_cast<std::uint64_t>(index);
  return {counter_bits(stream, i, 0), counter_bits(stream, i, 1), counter_bits(stream, i, 2)};
}

double rms_standard_error(const Eigen::Ref<const Eigen::VectorXd>& x, int batches) {
  const Eigen::Index n = x.size();
  if (batches < 2 || n < batches) return std::numeric_limits<double>::quiet_NaN();
  // Batch b holds samples [b n / B, (b + 1) n / B): every sample in one batch.
  Eigen::VectorXd means(batches);
  for (int b = 0; b < batches; ++b) {
    const Eigen::Index begin = b * n / batches, end = (b + 1) * n / batches;
    means(b) = x.segment(begin, end - begin).squaredNorm() / static_cast<double>(end - begin);
  }
  const double mean_square = x.squaredNorm() / static_cast<double>(n);
  if (!(mean_square > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double variance = (means.array() - means.mean()).square().sum() / (batches - 1);
  // SE(mean of x²) = sqrt(variance / B); RMS = sqrt(m): dRMS = dm / (2 RMS).
  return std::sqrt(variance / batches) / (2 * std::sqrt(mean_square));
}

json simulation_not_run(double seconds, const std::string& why) {
  return empty_simulation(seconds, "not run: " + why);
}

void put_simulation_not_run(json& line, double seconds) {
  if (line.contains("sim")) return;
  const std::string status = line.value("status", std::string());
  const std::string why = status == "unstable" ? "the linear loop is unstable: it diverges"
                          : status.rfind("refused", 0) == 0 ? "the sample is refused"
                          : status == "stable"              ? "the sample's loop was not built"
                                                            : "the sample's linear figures failed";
  line["sim"] = simulation_not_run(seconds, why);
}

json simulate_sample(const scene::ScenePlant& p, const scene::SampledScene& sampled, double seconds,
                     const SimulationSeeds& seeds) {
  try {
    return run_figures(sample_artefact(p, sampled, seconds, seeds), seconds);
  } catch (const std::exception& e) {
    return empty_simulation(seconds, std::string("error: ") + e.what());
  }
}

}  // namespace flexloop::campaign
