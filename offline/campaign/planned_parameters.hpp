// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Planning the uncertain parameters on a machine: each [[parameter]] path matched against the
// numbers of the machine's model and scene (offline/campaign/parameter_paths.hpp), each match's
// distribution made with its nominal value, and every draw judged physical before any sample
// runs (doc/campaign.md "Unphysical draws"). The result is the plan's "parameters" and
// "columns" (one column per design dimension), and what a unit point of the design makes of them.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "offline/campaign/parameter_paths.hpp"
#include "offline/campaign/uncertain_parameters.hpp"

namespace flexloop::campaign {

/// One design dimension: the concrete paths that take its draw (one for draw = "each", every
/// match for "shared") and each one's distribution.
struct PlannedColumn {
  std::string name;           ///< the concrete path, or the parameter's pattern when shared
  std::size_t parameter = 0;  ///< its [[parameter]] entry (0-based)
  std::vector<std::string> paths;
  std::vector<Distribution> distributions;
};

/// @throws flexloop::InputError "U.toml:line: ..." for a path that names nothing (with the
///         nearest valid names), a number two entries draw, a draw that is not physical (with
///         the remedy: truncated_normal, or bounds inside the physical range), controller.*
///         paths with a frozen controller.
std::vector<PlannedColumn> plan_columns(const UncertainParameters& u, const MachineDocuments& docs,
                                        const std::string& controller);

/// The plan's "parameters" (each entry with its matches and their distributions) and "columns".
nlohmann::json parameters_json(const UncertainParameters& u, const std::vector<PlannedColumn>& c);
nlohmann::json columns_json(const std::vector<PlannedColumn>& columns);
/// The columns back from a plan's "parameters" and "columns".
std::vector<PlannedColumn> columns_from_plan(const nlohmann::json& plan);

/// The values of a unit point (one coordinate per column): {concrete path: value}, in column
/// order.
ParameterValues values_at(const std::vector<PlannedColumn>& columns, const std::vector<double>& u);

}  // namespace flexloop::campaign
