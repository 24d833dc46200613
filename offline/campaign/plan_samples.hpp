// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Sample i of a plan (doc/campaign.md "How a sample is computed"): the design's unit point i
// (unit_point: a pure function of the design, n, d, seed and i), each coordinate mapped to its
// parameters by their inverse CDFs, the machine made with those values by the project's readers
// (offline/campaign/parameter_paths.hpp), and its figures by the SampleEvaluator built once from
// the nominal machine. The line depends on the plan and i alone: the same bytes whatever shard,
// process or engine computes it.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "offline/campaign/parameter_paths.hpp"
#include "offline/campaign/planned_parameters.hpp"
#include "offline/campaign/sample_figures.hpp"

namespace flexloop::campaign {

class PlanSamples {
 public:
  /// Reads the plan's scene and model (unchanged since planning: checked by the caller).
  explicit PlanSamples(const nlohmann::json& plan);

  /// The drawn values of evaluation `index`, {concrete path: value} in column order.
  ParameterValues values(long index) const;
  /// Its JSONL object: plan_id, index, parameters and the figures. A machine the readers refuse
  /// (a drawn value outside what a file may hold) is status "refused: ..." with null figures.
  nlohmann::json line(long index) const;
  /// The figures of the machine with `values` (any point of the parameters' ranges, not only a
  /// design's: the worst-machine search), as line() computes them, without the sample's identity
  /// and without a simulation.
  nlohmann::json figures_at(const ParameterValues& values) const;
  /// The same for a machine with the given drawn values (a point no design of the plan makes:
  /// subset simulation's chains, offline/campaign/subset_campaign.hpp), numbered `index`.
  nlohmann::json line_of(const ParameterValues& values, long index) const;
  /// The JSONL object of an evaluation that was not computed (its run crashed on it): its
  /// parameters, `status` and null figures.
  nlohmann::json failed_line(long index, const std::string& status) const;
  const MachineDocuments& documents() const { return docs_; }
  const std::vector<PlannedColumn>& columns() const { return columns_; }
  const nlohmann::json& nominal() const { return evaluator_.nominal(); }

 private:
  // The figures with the sample's plan_id, index and parameters.
  nlohmann::json figures_of(const ParameterValues& values,
                            const std::optional<SimulationSeeds>& seeds) const;
  nlohmann::json with_identity(nlohmann::json figures, long index,
                               const ParameterValues& values) const;
  nlohmann::json plan_;
  MachineDocuments docs_;
  std::vector<PlannedColumn> columns_;
  SampleEvaluator evaluator_;
};

/// The figures of a machine that was not evaluated: every figure field null.
nlohmann::json figures_not_computed(const std::string& status);

}  // namespace flexloop::campaign
