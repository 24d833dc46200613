// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `flexloop analyse SCENE`: the passive machine, the PI force-feedback design and the closed
// loop of a scene (doc/design.md §4), printed and written to a directory. A statically unstable
// plant (a preload beyond buckling) is reported with its modes and nothing further.
#include <nlohmann/json.hpp>
#include <string>

#include "plant/lti/modal_analysis.hpp"

namespace flexloop::pipeline {

/// analysis.json's "static_stability" (both analyse paths): the verdict, its figures and the
/// sentence plant::lti::to_string prints.
nlohmann::json static_stability_json(const plant::lti::StaticStability& s);

struct FrequencyGrid {
  double f_min_hz, f_max_hz;
  int points;
};

struct AnalyseOptions {
  /// The superelement reduction's error against the full FE body (reduction_error_report.hpp);
  /// a model without a superelement has none to measure.
  bool reduction_error = true;
};

void analyse_scene(const std::string& scene_path, const std::string& out_dir,
                   const FrequencyGrid& grid, const AnalyseOptions& options = {});

}  // namespace flexloop::pipeline
