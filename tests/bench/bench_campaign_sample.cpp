// SPDX-License-Identifier: BSD-3-Clause
// Cost of one campaign sample (issue 47, "Speed and scale"; doc/performance.md): the metrology
// frame (tools/scenes/metrology_frame.toml) with its six strut stiffnesses changed by a few %,
// re-linearised, discretised, closed, its stationary RMS by the discrete Lyapunov equation
// (closed and open loop), its disk margins and its closed-loop sigma_max on a 100-point grid.
// Target: <= 20 ms on one core.
//
//  - BM_CampaignSample: SampleEvaluator::evaluate, frozen controller (the nominal machine's PI).
//  - BM_CampaignSampleSteps: one pass through the steps evaluate takes, each timed; counters in
//    CPU seconds per sample (this thread's: tests/bench/lap_timer.hpp): linearise
//    (build_scene_plant: linearisation, modes, plant, PI loop), discretise (sample_scene), close
//    (the sampled loop's stability: scene::sampled_loop), lyapunov (stationary_rms closed and
//    open), margins (loop_disk_margins), sigma (closed_loop_response and its largest singular
//    values).
//
// Run from the repository root: build/check/tests/bench/bench_campaign_sample
#include <benchmark/benchmark.h>

#include <vector>

#include "offline/campaign/sample_figures.hpp"
#include "offline/pipeline/loop_figures.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/model/model_parser.hpp"
#include "tests/bench/lap_timer.hpp"

using namespace flexloop;

namespace {

constexpr const char* kScene = "tools/scenes/metrology_frame.toml";

// The frame with strut i's stiffness times 1 + 0.01 (i - 2.5): -2.5 % .. +2.5 %.
plant::model::Model machine(const scene::Scene& sc) {
  plant::model::Model m = plant::model::load_model(sc.model_path);
  int strut = 0;
  for (auto& el : m.elements)
    if (el.type == plant::model::ElementType::kTruss && el.stiffness.size() > 0 &&
        el.stiffness(0, 0) > 0)
      el.stiffness(0, 0) *= 1 + 0.01 * (strut++ - 2.5);
  return m;
}

campaign::SampleSettings settings() {
  return {campaign::ControllerMode::kFrozen, plant::lti::log_frequency_grid_hz(0.1, 1000, 100)};
}

void BM_CampaignSample(benchmark::State& state) {
  const scene::Scene sc = scene::load_scene(kScene);
  const campaign::SampleEvaluator evaluator(sc, plant::model::load_model(sc.model_path),
                                            settings());
  const plant::model::Model m = machine(sc);
  for (auto _ : state) {
    const auto j = evaluator.evaluate(sc, m);
    benchmark::DoNotOptimize(j);
  }
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CampaignSample)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_CampaignSampleSteps(benchmark::State& state) {
  const scene::Scene sc = scene::load_scene(kScene);
  const plant::model::Model nominal = plant::model::load_model(sc.model_path), m = machine(sc);
  scene::ScenePlantOptions frozen;
  frozen.pi_gains = scene::build_scene_plant(sc, nominal).gains;
  const std::vector<double> grid = settings().sigma_grid_hz;
  double t_lin = 0, t_disc = 0, t_close = 0, t_lyap = 0, t_margins = 0, t_sigma = 0;
  for (auto _ : state) {
    bench::LapTimer timer;
    auto lap = [&timer](double& acc) { timer.lap(acc); };
    const scene::ScenePlant p = scene::build_scene_plant(sc, m, frozen);
    lap(t_lin);
    const scene::SampledScene sampled = scene::sample_scene(p);
    lap(t_disc);
    const scene::SampledLoop loop = scene::sampled_loop(p);
    lap(t_close);
    const Eigen::VectorXd rms = pipeline::stationary_rms(p, sampled, true),
                          rms_open = pipeline::stationary_rms(p, sampled, false);
    lap(t_lyap);
    const auto margins = pipeline::loop_disk_margins(p);
    lap(t_margins);
    const Eigen::VectorXd sigma =
        pipeline::largest_singular_values(pipeline::closed_loop_response(p, &sampled, grid));
    lap(t_sigma);
    benchmark::DoNotOptimize(loop.stability.spectral_radius);
    benchmark::DoNotOptimize(rms.data());
    benchmark::DoNotOptimize(rms_open.data());
    benchmark::DoNotOptimize(margins.all_loops.alpha);
    benchmark::DoNotOptimize(sigma.data());
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["linearise_s"] = t_lin / it;
  state.counters["discretise_s"] = t_disc / it;
  state.counters["close_s"] = t_close / it;
  state.counters["lyapunov_s"] = t_lyap / it;
  state.counters["margins_s"] = t_margins / it;
  state.counters["sigma_s"] = t_sigma / it;
}
BENCHMARK(BM_CampaignSampleSteps)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
