// SPDX-License-Identifier: BSD-3-Clause
// `campaign --simulate S` (offline/campaign/sample_simulation.hpp): each stable sample's loop run
// by `flexloop sim`'s code. References: the sample's Lyapunov RMS (the loop made linear) with a
// tolerance derived from independent runs of the same machine (16 other seeds: the scatter of an
// RMS over S seconds), a saturating actuator whose lost damping raises the RMS, the same bytes
// however often and in which order a sample is computed, and an unstable loop that is not run.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "numeric/constants.hpp"
#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/campaign_report.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/campaign/sample_simulation.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/scene_plant.hpp"
#include "online/sim/scene_runs.hpp"

namespace {

// Using-declarations, not directives: the area's test files share unity batches.
using flexloop::campaign::make_plan;
using flexloop::campaign::PlanRequest;
using flexloop::campaign::PlanSamples;
using nlohmann::json;

constexpr const char* kSimulate = "tests/fixtures/one_strut_simulate.toml";
constexpr const char* kSaturating = "tests/fixtures/one_strut_saturating.toml";
constexpr const char* kUncertain = "tests/fixtures/one_strut_simulate_uncertain.toml";
constexpr const char* kChannel = "acc:y.mass";
constexpr double kSeconds = 4;

json simulated_plan(const char* scene_file, long n, double seconds = kSeconds) {
  PlanRequest r;
  r.scene = scene_file;
  r.uncertain = kUncertain;
  r.n = n;
  r.seed = 5;
  r.grid_points = 20;
  r.simulate_s = seconds;
  return make_plan(r);
}

// The RMS of `kChannel` over kSeconds in `replicas` runs of sample `index`'s loop, each with its
// own seeds (none the campaign's): independent draws of the simulated RMS. The loop is built as
// the campaign's frozen controller has it: the nominal machine's PI gains on the sample.
std::vector<double> replica_rms(const PlanSamples& samples, long index, int replicas) {
  const auto& docs = samples.documents();
  const auto m = docs.apply(samples.values(index));
  flexloop::scene::ScenePlantOptions frozen;
  frozen.pi_gains =
      flexloop::scene::build_scene_plant(docs.nominal_machine().scene, docs.nominal_machine().model)
          .gains;
  const auto p = flexloop::scene::build_scene_plant(m.scene, m.model, frozen);
  auto a = flexloop::scene::build_loop_artefact(p, flexloop::scene::sample_scene(p),
                                                flexloop::artefact::PlantForm::kDense);
  flexloop::sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(kSeconds / s.dt);
  flexloop::sim::SceneRunOptions on_only;
  on_only.on_only = true;
  std::vector<double> out;
  for (int r = 0; r < replicas; ++r) {
    a.floor.seed = 1000 + static_cast<std::uint64_t>(r);
    a.effects.force_sensor.seed = 2000 + static_cast<std::uint64_t>(r);
    out.push_back(flexloop::sim::run_artefact(a, s, on_only).on.rms_performance(0));
  }
  return out;
}

double mean(const std::vector<double>& xs) {
  double sum = 0;
  for (double x : xs) sum += x;
  return sum / static_cast<double>(xs.size());
}

double standard_deviation(const std::vector<double>& xs) {
  const double m = mean(xs);
  double sum = 0;
  for (double x : xs) sum += (x - m) * (x - m);
  return std::sqrt(sum / static_cast<double>(xs.size() - 1));
}

}  // namespace

TEST_CASE(
    "simulate: for 3 samples without saturation the simulated RMS is the Lyapunov RMS within 4 "
    "standard deviations of a run of S seconds, measured on 16 independent runs",
    "[campaign][simulate]") {
  // Tolerance: the simulated RMS over S s scatters from seed to seed with a standard deviation
  // sigma_S, which 16 runs of the same machine with other seeds estimate (to about 18 %). A run
  // beyond 4 sigma_S of the exact value has probability below 1e-4 (the RMS over S >> the loop's
  // correlation time is near normal), so the tolerance is 4 sigma_S; the 16 runs' mean must lie
  // within 4 sigma_S / 4 of it (the linear loop's simulation has no bias).
  const json plan = simulated_plan(kSimulate, 3);
  const PlanSamples samples(plan);
  for (long i = 0; i < 3; ++i) {
    const json line = samples.line(i);
    REQUIRE(line["status"] == "stable");
    const json& s = line["sim"];
    REQUIRE(s["status"] == "ran");
    CHECK(s["seconds"].get<double>() == kSeconds);
    CHECK(s["start"] == "stationary (closed loop)");
    CHECK(s["saturated_share"]["stress:e1.strut"].get<double>() == 0);
    CHECK(s["max_abs_command"]["stress:e1.strut"].get<double>() < 500);
    const double lyapunov = line["rms"][kChannel].get<double>();
    const double run = s["rms"][kChannel].get<double>();
    const double se = s["rms_standard_error"][kChannel].get<double>();
    const std::vector<double> replicas = replica_rms(samples, i, 16);
    const double sigma = standard_deviation(replicas);
    INFO("sample " << i << ": run " << run << ", Lyapunov " << lyapunov << ", replicas' mean "
                   << mean(replicas) << " sd " << sigma << ", batch-means SE " << se);
    CHECK(std::abs(run - lyapunov) <= 4 * sigma);
    CHECK(std::abs(mean(replicas) - lyapunov) <= 4 * sigma / 4);
    // The line's own standard error (batch means over the one run) is the replicas' scatter:
    // 20 batches and 16 runs each estimate it to about 18 %, so a factor 2 is over 4 of theirs.
    CHECK(se >= sigma / 2);
    CHECK(se <= 2 * sigma);
  }
}

TEST_CASE(
    "simulate: where a tight actuator limit bites, the saturated share is above 0 and the "
    "simulated RMS above the Lyapunov RMS (the clipped force feedback damps less)",
    "[campaign][simulate]") {
  // The limit bites in bursts (under 1 % of the samples) that raise the RMS by about 10 %: a run
  // must hold many of them for its standard error to fall to about 2 %, hence 160 s. Or the loop
  // falls into a saturated limit cycle, the linear loop stable all the same (its RMS a thousand
  // times the Lyapunov RMS, more than half the samples at the limit): 2 of these 3 samples do
  // within 160 s. Either raises the RMS.
  const double seconds = 160;
  const json plan = simulated_plan(kSaturating, 3, seconds);
  const PlanSamples samples(plan);
  std::vector<json> lines;
  for (long i = 0; i < 3; ++i) {
    const json line = samples.line(i);
    REQUIRE(line["status"] == "stable");
    const json& s = line["sim"];
    REQUIRE(s["status"] == "ran");
    const double share = s["saturated_share"]["stress:e1.strut"].get<double>();
    const double run = s["rms"][kChannel].get<double>();
    const double se = s["rms_standard_error"][kChannel].get<double>();
    const double lyapunov = line["rms"][kChannel].get<double>();
    INFO("sample " << i << ": saturated share " << share << ", run " << run << " +- " << se
                   << ", Lyapunov " << lyapunov);
    CHECK(share > 0);
    CHECK(share < 1);
    // The PI's command is clamped at the limit: its largest |u| is the limit (gain 1).
    CHECK(s["max_abs_command"]["stress:e1.strut"].get<double>() == Approx(10.0).epsilon(1e-9));
    // Above the exact linear value by more than 4 of the run's standard errors.
    CHECK(run - lyapunov > 4 * se);
    lines.push_back(line);
  }
  // The report's ratio figure: its median over the 3 samples is the middle ratio.
  const json summary = flexloop::campaign::campaign_summary(plan, lines);
  std::vector<double> ratios;
  for (const json& l : lines)
    ratios.push_back(l["sim"]["rms"][kChannel].get<double>() / l["rms"][kChannel].get<double>());
  std::sort(ratios.begin(), ratios.end());
  const json& f = summary["figures"][std::string("sim.rms_ratio.") + kChannel];
  CHECK(f["n"] == 3);
  CHECK(f["quantiles"][1]["estimate"].get<double>() == ratios[1]);
  CHECK(summary["figures"].contains("sim.saturated_share.stress:e1.strut"));
  CHECK(summary["simulation"]["ran"] == 3);
  CHECK(summary["simulation"]["seconds"].get<double>() == seconds);
}

TEST_CASE(
    "simulate: a sample's line is the same bytes computed again, in another order, by another "
    "evaluator, and a plan without --simulate has no sim and no simulate_s",
    "[campaign][simulate]") {
  const json plan = simulated_plan(kSaturating, 3);
  const PlanSamples first(plan), second(plan);
  std::vector<std::string> forward, backward(3);
  for (long i = 0; i < 3; ++i) forward.push_back(first.line(i).dump());
  for (long i = 2; i >= 0; --i) backward[static_cast<std::size_t>(i)] = second.line(i).dump();
  CHECK(forward == backward);
  CHECK(first.line(1).dump() == forward[1]);
  // Other samples, other seeds: another run.
  CHECK(json::parse(forward[0])["sim"]["rms"] != json::parse(forward[1])["sim"]["rms"]);

  PlanRequest r;
  r.scene = kSaturating;
  r.uncertain = kUncertain;
  r.n = 1;
  r.seed = 5;
  r.grid_points = 20;
  const json linear = make_plan(r);
  CHECK_FALSE(linear.contains("simulate_s"));
  CHECK(linear["plan_id"] != plan["plan_id"]);
  CHECK_FALSE(PlanSamples(linear).line(0).contains("sim"));
}

TEST_CASE("simulate: an unstable loop is not run, and says why", "[campaign][simulate]") {
  // tests/fixtures/one_strut_200hz.toml: the one-strut loop at a rate it is unstable at.
  const flexloop::scene::Scene sc =
      flexloop::scene::load_scene("tests/fixtures/one_strut_200hz.toml");
  const auto model = flexloop::plant::model::load_model(sc.model_path);
  const flexloop::campaign::SampleEvaluator evaluator(
      sc, model, {flexloop::campaign::ControllerMode::kFrozen, {}, 1.0});
  const json j = evaluator.evaluate(sc, model, flexloop::campaign::simulation_seeds(1, 0));
  REQUIRE(j["status"] == "unstable");
  CHECK(j["sim"]["status"] == "not run: the linear loop is unstable: it diverges");
  CHECK(j["sim"]["rms"].is_null());
  CHECK(j["sim"]["seconds"].get<double>() == 1.0);
  // Without seeds (the plan's nominal machine) no run is asked for.
  CHECK_FALSE(evaluator.evaluate(sc, model).contains("sim"));
}

TEST_CASE("simulate: the RMS's batch-means standard error of white noise is sigma / sqrt(2 N)",
          "[campaign][simulate]") {
  // x_k = +-1 alternating in blocks: every batch's mean square is exactly 1, so the standard
  // error is 0; too few samples for the batches give NaN.
  Eigen::VectorXd ones = Eigen::VectorXd::Ones(400);
  for (Eigen::Index k = 0; k < ones.size(); k += 2) ones(k) = -1;
  CHECK(flexloop::campaign::rms_standard_error(ones, 20) == 0);
  CHECK(std::isnan(flexloop::campaign::rms_standard_error(Eigen::VectorXd::Ones(10), 20)));
  // Gaussian white noise of unit variance: Var(x²) = 2, SE(mean x²) = sqrt(2 / N) and
  // SE(RMS) = sqrt(2 / N) / 2 = 1 / sqrt(2 N). Averaged over 200 series of N = 2000 (the
  // batch-means estimate scatters by about 1 / sqrt(2 * 19) = 16 % per series): within 5 %.
  const long n = 2000;
  double sum = 0;
  std::uint64_t state = 12345;
  const auto gaussian = [&state] {  // Box-Muller on SplitMix64's words
    const auto unit = [&state] {
      state += 0x9E3779B97F4A7C15ull;
      std::uint64_t z = state;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      return (static_cast<double>((z ^ (z >> 31)) >> 11) + 0.5) * 0x1p-53;
    };
    return std::sqrt(-2 * std::log(unit())) * std::cos(flexloop::numeric::kTwoPi * unit());
  };
  for (int series = 0; series < 200; ++series) {
    Eigen::VectorXd x(n);
    for (Eigen::Index k = 0; k < n; ++k) x(k) = gaussian();
    sum += flexloop::campaign::rms_standard_error(x, 20);
  }
  CHECK(sum / 200 == Approx(1 / std::sqrt(2.0 * n)).epsilon(0.05));
}

TEST_CASE(
    "simulate: sim's controller-on run alone (on_only) is the on run of its two, to the bit, and "
    "leaves the off run empty",
    "[campaign][simulate]") {
  const auto sc = flexloop::scene::load_scene(kSaturating);
  const auto p = flexloop::scene::build_scene_plant(sc);
  const auto a = flexloop::scene::build_loop_artefact(p, flexloop::scene::sample_scene(p),
                                                      flexloop::artefact::PlantForm::kDense);
  flexloop::sim::RunSettings s;
  s.dt = a.dt();
  s.steps = 4000;
  flexloop::sim::SceneRunOptions alone;
  alone.on_only = true;
  const auto both = flexloop::sim::run_artefact(a, s, {});
  const auto on = flexloop::sim::run_artefact(a, s, alone);
  CHECK(on.on.rms_performance == both.on.rms_performance);
  CHECK(on.on.rms_command == both.on.rms_command);
  CHECK(on.off.rms_performance.size() == 0);
  CHECK(both.off.rms_performance.size() == 1);
}
