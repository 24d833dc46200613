// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/sample_figures.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/input_error.hpp"
#include "controller/design/sampled_loop_stability.hpp"
#include "offline/pipeline/loop_figures.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/modal_analysis.hpp"

namespace flexloop::campaign {

namespace {

using nlohmann::json;

// Every figure of the contract, not computed yet.
json empty_figures() {
  return {{"status", nullptr},
          {"spectral_radius", nullptr},
          {"largest_inner_radius", nullptr},
          {"natural_frequencies_hz", nullptr},
          {"rms", nullptr},
          {"rms_open", nullptr},
          {"disk_margin_db", nullptr},
          {"disk_margin_deg", nullptr},
          {"disk_margin_all_db", nullptr},
          {"disk_margin_all_deg", nullptr},
          {"peak_sigma", nullptr},
          {"sigma_max", nullptr}};
}

json to_json(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// {performance channel: value}.
json per_channel(const std::vector<std::string>& channels, const Eigen::VectorXd& v) {
  json j = json::object();
  for (std::size_t i = 0; i < channels.size(); ++i)
    j[channels[i]] = v(static_cast<Eigen::Index>(i));
  return j;
}

// The balanced disk's gain margin in dB, 20 log10 of its upper factor (2 + a)/(2 - a): "+inf"
// when the disk reaches a >= 2, where no gain increase destabilises the loop (the best machines:
// an order statistic, not a missing value).
json margin_db(const controller::design::DiskMargin& m) {
  return std::isfinite(m.gain_high) ? json(20 * std::log10(m.gain_high)) : json("+inf");
}

// The stationary RMS, or null when the loop has no stationary state (its modes on the unit
// circle not resolved): a stable loop can still lack one. `why` gets the reason.
json rms_or_null(const scene::ScenePlant& p, const scene::SampledScene& sampled, bool closed,
                 std::string* why = nullptr) {
  try {
    return per_channel(p.scene.performance, pipeline::stationary_rms(p, sampled, closed));
  } catch (const std::invalid_argument& e) {
    if (why) *why = e.what();
    return nullptr;
  }
}

// The disk margins: the worst loop at a time (the smallest disk) and all at once. Left null
// when a loop pole sits on the unit circle at a grid frequency.
void put_disk_margins(const scene::ScenePlant& p, json& j) {
  controller::design::InputDiskMargins m;
  try {
    m = pipeline::loop_disk_margins(p);
  } catch (const std::domain_error&) {
    return;
  }
  if (m.loops.empty()) return;
  const controller::design::DiskMargin* worst = &m.loops.front();
  for (const auto& loop : m.loops)
    if (loop.alpha < worst->alpha) worst = &loop;
  j["disk_margin_db"] = margin_db(*worst);
  j["disk_margin_deg"] = worst->phase_deg;
  j["disk_margin_all_db"] = margin_db(m.all_loops);
  j["disk_margin_all_deg"] = m.all_loops.phase_deg;
}

// sigma_max on the grid and its peak.
void put_sigma(const scene::ScenePlant& p, const scene::SampledScene& sampled,
               const std::vector<double>& grid_hz, json& j) {
  if (grid_hz.empty()) return;
  const Eigen::VectorXd sigma =
      pipeline::largest_singular_values(pipeline::closed_loop_response(p, &sampled, grid_hz));
  j["sigma_max"] = to_json(sigma);
  j["peak_sigma"] = sigma.maxCoeff();
}

// The figures of a machine whose plant is built; throws what the pipeline refuses. Returns the
// sampled scene (a simulation runs it).
scene::SampledScene put_loop_figures(const scene::ScenePlant& p, const std::vector<double>& grid_hz,
                                     json& j) {
  scene::SampledScene sampled = scene::sample_scene(p);
  const scene::SampledLoop loop = scene::sampled_loop(p);
  j["spectral_radius"] = loop.stability.spectral_radius;
  // The PI integrator's poles sit on the unit circle (z = 1) in every stable machine, so the
  // spectral radius is 1 there: the poles inside show how far a machine is from instability.
  j["largest_inner_radius"] = loop.stability.largest_inner_radius;
  j["rms_open"] = rms_or_null(p, sampled, false);
  if (!pipeline::closed_loop_stable(p, loop.stability)) {
    j["status"] = "unstable";
    return sampled;
  }
  std::string why;
  j["rms"] = rms_or_null(p, sampled, true, &why);
  // Judged stable without a stationary state: its own status, not a stable machine without RMS.
  j["status"] = j["rms"].is_null()
                    ? "marginal: the closed loop has no stationary state (" + why + ")"
                    : std::string("stable");
  put_disk_margins(p, j);
  put_sigma(p, sampled, grid_hz, j);
  return sampled;
}

// The largest |z| of the poles inside the unit circle (not within rounding of it): a passive
// machine's rigid-body or undamped modes sit on the circle, the rest is how fast it settles.
double largest_inner_radius(const Eigen::MatrixXd& a) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(a, false);
  double largest = 0;
  for (const auto& z : es.eigenvalues())
    if (std::abs(z) < 1 - controller::design::kSampledRoundingTolerance)
      largest = std::max(largest, std::abs(z));
  return largest;
}

// The passive machine alone (an open-loop campaign: the scene has no controller): its sampled
// plant's spectral radius, its stationary RMS and the floor -> performance path's sigma. Unstable
// above the unit circle by more than rounding; marginal without a stationary state (an undamped
// or rigid-body mode).
scene::SampledScene put_passive_figures(const scene::ScenePlant& p,
                                        const std::vector<double>& grid_hz, json& j) {
  scene::SampledScene sampled = scene::sample_scene(p);
  const double radius = sampled.plant.spectral_radius;
  j["spectral_radius"] = radius;
  j["largest_inner_radius"] = largest_inner_radius(sampled.plant.sys.A);
  if (radius > 1 + controller::design::kSampledRoundingTolerance) {
    j["status"] = "unstable";
    return sampled;
  }
  std::string why;
  j["rms_open"] = rms_or_null(p, sampled, false, &why);
  j["status"] = j["rms_open"].is_null()
                    ? "marginal: the passive machine has no stationary state (" + why + ")"
                    : std::string("stable");
  if (!grid_hz.empty()) {
    const Eigen::VectorXd sigma = pipeline::largest_singular_values(
        plant::lti::frequency_response(pipeline::floor_to_performance(p), grid_hz));
    j["sigma_max"] = to_json(sigma);
    j["peak_sigma"] = sigma.maxCoeff();
  }
  return sampled;
}

}  // namespace

SampleEvaluator::SampleEvaluator(const scene::Scene& nominal_scene,
                                 const plant::model::Model& nominal_model, SampleSettings settings)
    : settings_(std::move(settings)) {
  const auto& c = nominal_scene.controller;
  if (c.enabled && c.type == "fmu")
    throw common::InputError(nominal_scene.file,
                             "[controller]: a controller FMU cannot be seen into: a campaign "
                             "needs its matrices (use type \"pi_force_feedback\" or "
                             "\"state_space\")");
  const scene::ScenePlant p = scene::build_scene_plant(nominal_scene, nominal_model);
  open_loop_ = !scene::has_controller(p);
  if (!p.statics.stable())
    throw common::InputError(nominal_scene.file, "the nominal machine is statically unstable: " +
                                                     plant::lti::to_string(p.statics));
  pi_ = scene::has_pi_controller(p);
  nominal_gains_ = p.gains;
  nominal_ = evaluate(nominal_scene, nominal_model);
}

json SampleEvaluator::evaluate(const scene::Scene& scene, const plant::model::Model& model,
                               const std::optional<SimulationSeeds>& seeds) const {
  const bool simulate = seeds && settings_.simulate_s > 0;
  json j = machine_figures(scene, model, simulate ? seeds : std::nullopt);
  if (simulate) put_simulation_not_run(j, settings_.simulate_s);
  return j;
}

json SampleEvaluator::machine_figures(const scene::Scene& scene, const plant::model::Model& model,
                                      const std::optional<SimulationSeeds>& seeds) const {
  json j = empty_figures();
  try {
    scene::ScenePlantOptions options;
    if (pi_ && settings_.mode == ControllerMode::kFrozen) options.pi_gains = nominal_gains_;
    const scene::ScenePlant p = scene::build_scene_plant(scene, model, options);
    if (!p.statics.stable()) {
      j["status"] =
          "refused: the machine is statically unstable: " + plant::lti::to_string(p.statics);
      return j;
    }
    j["natural_frequencies_hz"] = to_json(p.natural_frequencies_hz);
    const scene::SampledScene sampled = open_loop_
                                            ? put_passive_figures(p, settings_.sigma_grid_hz, j)
                                            : put_loop_figures(p, settings_.sigma_grid_hz, j);
    if (seeds && j["status"] == "stable")
      j["sim"] = simulate_sample(p, sampled, settings_.simulate_s, *seeds);
  } catch (const common::InputError& e) {
    j = empty_figures();
    j["status"] = std::string("refused: ") + e.what();
  } catch (const std::exception& e) {
    j = empty_figures();
    j["status"] = std::string("error: ") + e.what();
  }
  return j;
}

}  // namespace flexloop::campaign
