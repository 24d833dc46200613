// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/campaign_plan.hpp"

#include <cmath>
#include <filesystem>

#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "offline/campaign/designs.hpp"
#include "offline/campaign/plan_file.hpp"
#include "offline/campaign/planned_parameters.hpp"
#include "offline/report/csv_writer.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/superelement/reduction_store.hpp"

namespace flexloop::campaign {

namespace {

std::string absolute_path(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

std::vector<double> sigma_grid_hz(const PlanRequest& r, const Machine& nominal) {
  if (!(r.f_min_hz > 0 && r.f_max_hz > r.f_min_hz && r.grid_points >= 2))
    throw common::InputError("--fmin/--fmax/--points",
                             "need 0 < fmin < fmax and at least 2 points");
  const scene::ScenePlant p = scene::build_scene_plant(nominal.scene);
  return plant::lti::with_resonances(
      plant::lti::log_frequency_grid_hz(r.f_min_hz, r.f_max_hz, r.grid_points),
      p.natural_frequencies_hz);
}

// --simulate holds each sample's run log in memory (offline/campaign/sample_simulation.hpp: the
// commands' saturation figures and the batch means come from it): refused at planning when one
// sample's log would pass kMaxSimulationLogBytes, before any shard allocates it.
constexpr double kMaxSimulationLogBytes = 1e9;

void require_simulation_fits(const scene::Scene& sc, double seconds) {
  const auto columns = static_cast<double>(1 + sc.disturbances.size() + 2 * sc.performance.size() +
                                           sc.sensors.size() + sc.actuators.size());
  const double bytes_per_second = sc.discretisation.rate_hz * columns * sizeof(double);
  if (seconds * bytes_per_second <= kMaxSimulationLogBytes) return;
  throw common::InputError(
      "--simulate",
      "a sample's run of " + report::format_number(seconds) + " s logs " +
          report::format_number(std::ceil(seconds * bytes_per_second / 1e6)) +
          " MB in memory (its outputs and commands at " +
          report::format_number(sc.discretisation.rate_hz) + " Hz); at most " +
          report::format_number(kMaxSimulationLogBytes / 1e6) + " MB: simulate at most " +
          report::format_number(std::floor(kMaxSimulationLogBytes / bytes_per_second)) + " s");
}

}  // namespace

ControllerMode controller_mode_from_name(const std::string& name) {
  if (name == "frozen") return ControllerMode::kFrozen;
  if (name == "redesigned") return ControllerMode::kRedesigned;
  throw common::InputError("--controller", "'" + name + "' is not frozen or redesigned");
}

double plan_simulate_s(const nlohmann::json& plan) {
  return plan.contains("simulate_s") ? plan["simulate_s"].get<double>() : 0.0;
}

void keep_reductions_beside(const std::string& plan_path) {
  plant::superelement::set_reduction_store(
      (std::filesystem::path(plan_path).parent_path() / "reductions").string());
}

nlohmann::json make_plan(const PlanRequest& r) {
  if (r.n < 1)
    throw common::InputError(
        "-n", "a campaign needs at least one sample (n = " + std::to_string(r.n) + ")");
  if (!(std::isfinite(r.simulate_s) && r.simulate_s >= 0))
    throw common::InputError("--simulate",
                             "the simulated time per sample must be a finite "
                             "number of seconds (0: none)");
  const DesignKind design = design_kind_from_name(r.design);
  const UncertainParameters u = load_uncertain_parameters(r.uncertain);
  const std::string controller = r.controller.empty() ? u.controller : r.controller;
  const ControllerMode mode = controller_mode_from_name(controller);
  // Everything the plan holds by absolute path, so that its id does not depend on where the
  // command ran (the nominal artefact's provenance names the scene as it was given).
  const std::string scene_path = absolute_path(r.scene);
  const MachineDocuments docs(scene_path);
  require_simulation_fits(docs.nominal_machine().scene, r.simulate_s);
  const std::vector<PlannedColumn> columns = plan_columns(u, docs, controller);

  nlohmann::json plan{{"format", kPlanFormat}, {"version", kPlanVersion}};
  plan["scene"] = scene_path;
  plan["scene_sha256"] = common::file_sha256(scene_path);
  plan["model"] = absolute_path(docs.model_file());
  plan["model_sha256"] = common::file_sha256(docs.model_file());
  plan["uncertain"] = absolute_path(r.uncertain);
  plan["uncertain_sha256"] = common::file_sha256(r.uncertain);
  plan["nominal_artefact_sha256"] = nominal_artefact_sha256(scene_path);
  // Every other file the scene reads: the state-space controller (or an FMU) by its hash too.
  if (const std::string& file = docs.nominal_machine().scene.controller.file; !file.empty()) {
    plan["controller_file"] = absolute_path(file);
    plan["controller_file_sha256"] = common::file_sha256(file);
  }
  plan["controller"] = controller;
  plan["design"] = design_name(design);
  plan["seed"] = r.seed;
  plan["n"] = r.n;
  const int d = static_cast<int>(columns.size());
  plan["evaluations"] = evaluation_count(design, r.n, d);
  plan["parameters"] = parameters_json(u, columns);
  plan["columns"] = columns_json(columns);
  const std::vector<double> grid = sigma_grid_hz(r, docs.nominal_machine());
  plan["sigma_grid_hz"] = grid;
  const SampleEvaluator evaluator(docs.nominal_machine().scene, docs.nominal_machine().model,
                                  {mode, grid});
  plan["nominal"] = evaluator.nominal();
  // A scene without a controller: the passive fleet (closed plans carry no key: their ids stay).
  if (evaluator.open_loop()) plan["loop"] = "open";
  if (r.simulate_s > 0) plan["simulate_s"] = r.simulate_s;
  return with_plan_id(plan);
}

}  // namespace flexloop::campaign
