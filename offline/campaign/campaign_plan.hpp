// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Making a campaign's plan (`flexloop campaign plan`, doc/campaign.md): the scene, its model and
// the uncertain parameters (all by absolute path and SHA-256), the nominal loop artefact's hash,
// the planned parameters and design columns, the design, seed and n, the number of evaluations,
// the sigma grid, the nominal machine's figures and, with --simulate S, `simulate_s` (absent
// without: a plan made without it keeps its plan_id).
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "offline/campaign/sample_figures.hpp"

namespace flexloop::campaign {

struct PlanRequest {
  std::string scene, uncertain;
  long n = 0;
  std::string design = "random";  ///< random | lhs | sobol | saltelli
  std::uint64_t seed = 1;
  std::string controller;  ///< frozen | redesigned; empty: the uncertain file's [campaign]
  double f_min_hz = 0.1, f_max_hz = 1000;  ///< the sigma grid (log, with the nominal resonances)
  int grid_points = 200;
  double simulate_s = 0;  ///< > 0: each stable sample also runs its loop this long (0: off)
};

/// @throws flexloop::InputError for bad input (the files, n < 1, an unknown design, a simulated
/// time that is not a finite number >= 0, and what offline/campaign/planned_parameters.hpp
/// refuses).
nlohmann::json make_plan(const PlanRequest& request);

/// Superelements are reduced once per plan: the process that plans and every process that runs a
/// shard of it keep their reductions in `reductions/` beside the plan file (a superelement's
/// parameters are not drawn: every sample shares its reduction). Call before the model is read.
void keep_reductions_beside(const std::string& plan_path);

ControllerMode controller_mode_from_name(const std::string& name);

/// The plan's simulated seconds per sample: its `simulate_s`, 0 when absent (no simulation).
double plan_simulate_s(const nlohmann::json& plan);

}  // namespace flexloop::campaign
