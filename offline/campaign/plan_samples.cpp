// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/plan_samples.hpp"

#include "common/input_error.hpp"
#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/designs.hpp"
#include "offline/campaign/plan_file.hpp"

namespace flexloop::campaign {

PlanSamples::PlanSamples(const nlohmann::json& plan)
    : plan_(plan),
      docs_(plan.at("scene").get<std::string>()),
      columns_(columns_from_plan(plan)),
      evaluator_(docs_.nominal_machine().scene, docs_.nominal_machine().model,
                 {controller_mode_from_name(plan.at("controller").get<std::string>()),
                  plan.at("sigma_grid_hz").get<std::vector<double>>(), plan_simulate_s(plan)}) {}

ParameterValues PlanSamples::values(long index) const {
  const std::vector<double> u = unit_point(
      design_kind_from_name(plan_.at("design").get<std::string>()), plan_.at("n").get<long>(),
      static_cast<int>(columns_.size()), plan_.at("seed").get<std::uint64_t>(), index);
  return values_at(columns_, u);
}

nlohmann::json figures_not_computed(const std::string& status) {
  nlohmann::json j{{"status", status}};
  for (const char* figure :
       {"spectral_radius", "largest_inner_radius", "natural_frequencies_hz", "rms", "rms_open",
        "disk_margin_db", "disk_margin_deg", "disk_margin_all_db", "disk_margin_all_deg",
        "peak_sigma", "sigma_max"})
    j[figure] = nullptr;
  return j;
}

nlohmann::json PlanSamples::figures_of(const ParameterValues& values,
                                       const std::optional<SimulationSeeds>& seeds) const {
  try {
    const Machine m = docs_.apply(values);
    return evaluator_.evaluate(m.scene, m.model, seeds);
  } catch (const common::InputError& e) {
    return figures_not_computed(std::string("refused: the drawn machine: ") + e.what());
  } catch (const std::exception& e) {
    return figures_not_computed(std::string("error: ") + e.what());
  }
}

nlohmann::json PlanSamples::figures_at(const ParameterValues& values) const {
  return figures_of(values, std::nullopt);
}

nlohmann::json PlanSamples::line(long index) const {
  return line_of(values(index), index);
}

nlohmann::json PlanSamples::line_of(const ParameterValues& values, long index) const {
  const double simulate_s = plan_simulate_s(plan_);
  nlohmann::json figures =
      figures_of(values, simulation_seeds(plan_.at("seed").get<std::uint64_t>(), index));
  if (simulate_s > 0) put_simulation_not_run(figures, simulate_s);
  return with_identity(std::move(figures), index, values);
}

nlohmann::json PlanSamples::failed_line(long index, const std::string& status) const {
  nlohmann::json figures = figures_not_computed(status);
  if (const double simulate_s = plan_simulate_s(plan_); simulate_s > 0)
    put_simulation_not_run(figures, simulate_s);
  return with_identity(std::move(figures), index, values(index));
}

nlohmann::json PlanSamples::with_identity(nlohmann::json figures, long index,
                                          const ParameterValues& values) const {
  nlohmann::json parameters = nlohmann::json::object();
  for (const auto& [path, value] : values) parameters[path] = value;
  figures["plan_id"] = plan_.at("plan_id");
  figures["index"] = index;
  figures["parameters"] = parameters;
  figures["flexloop"] = line_build();  // report refuses shards of mixed builds
  return figures;
}

}  // namespace flexloop::campaign
