// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The worst machine in the box (`flexloop campaign worst`, doc/campaign.md "The worst machine"):
// a bounded search over the uncertain parameters' ranges for the machine whose figure is worst:
// the largest spectral radius, peak sigma or RMS, the smallest disk margin. The figure is the
// campaign sample's (offline/campaign/sample_figures.hpp): the machine re-linearised from its FE
// model, not an LFT model of it (the question MATLAB's wcdiskmargin / robstab answer).
//
// The box, in each column's unit coordinate u (the design's, offline/campaign/distributions.hpp):
// a column whose distributions are all uniform spans its bounds, u in [0, 1]; any other spans its
// quantiles [1e-6, 1 - 1e-6], or [Phi(-K), Phi(K)] with `sigmas` K.
// The search: n machines of a Latin hypercube over the distributions (their unit points clamped
// into the box), then a derivative-free bounded local search (NLopt's BOBYQA, Powell's bounded
// quadratic models: on the metrology frame's 15 parameters it reached in 51 machines the margin
// that Subplex had not approached in 300) from each of the `starts` worst of them, the budget
// `evaluations` shared between the starts. The result
// is the worst machine evaluated, samples included: never better than the worst one sampled.
// Worse than any number: an unstable loop for a figure an unstable loop does not have (a margin,
// a peak sigma, an RMS), and a marginal loop (no stationary state) for an RMS; it ends the search.
// A refused or failed machine is not a machine that runs: never the worst.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/parameter_paths.hpp"

namespace flexloop::campaign {

/// Which figure, and which way is worse.
struct WorstFigure {
  std::string name;               ///< spectral_radius | disk_margin_db | peak_sigma | rms.<channel>
  std::string channel;            ///< the RMS's performance channel
  bool smaller_is_worse = false;  ///< a margin
};

/// "spectral_radius", "largest_inner_radius" (the slowest pole inside the circle: a PI loop's
/// integrator sits on it), "disk_margin_db", "peak_sigma", "rms" (the scene's one performance
/// channel) or "rms.<channel>". @throws flexloop::InputError naming --figure and the choices.
WorstFigure worst_figure_from_name(const std::string& name,
                                   const std::vector<std::string>& performance_channels);

/// How bad a machine's figures are for `f`: larger is worse; +inf for a loop worse than any
/// number (above), -inf for a machine without the figure that is not worse (refused, failed, an
/// unbounded margin).
double badness(const nlohmann::json& figures, const WorstFigure& f);

struct WorstRequest {
  PlanRequest plan;  ///< scene, U.toml, n (the sampled machines), seed, controller, sigma grid
  std::string figure = "spectral_radius";
  double sigmas = 0;      ///< > 0: non-uniform columns span [Phi(-K), Phi(K)]
  int starts = 4;         ///< local searches, from the worst sampled machines
  int evaluations = 300;  ///< the local searches' budget, shared between them
};

/// One local search: where it started (a sampled machine), its figure there and at its end.
struct WorstStart {
  long sample = 0;  ///< the sampled machine it started from (0-based)
  double start_badness = 0, end_badness = 0;
  long evaluations = 0;
  std::string stopped;  ///< NLopt's reason
};

struct WorstMachine {
  WorstFigure figure;
  nlohmann::json figures;  ///< the worst machine's (sample_figures.hpp)
  double badness = 0;      ///< its badness(figures, figure)
  ParameterValues values;  ///< {path: value}
  std::vector<double> unit_point;
  std::vector<double> box_low, box_high;  ///< per column, in u
  std::vector<std::string> columns;
  long sampled = 0, evaluations = 0;  ///< machines sampled; every machine evaluated
  double worst_sampled_badness = 0;
  std::vector<WorstStart> starts;
  nlohmann::json plan;  ///< the sampled machines' plan (scene, hashes, design, seed)
};

/// Called after each evaluation with (done, budget).
using WorstProgress = std::function<void(long, long)>;

/// @throws flexloop::InputError for what make_plan refuses, a bad figure, sigmas <= 0 given,
/// starts < 1 or evaluations < 0.
WorstMachine find_worst_machine(const WorstRequest& request, const WorstProgress& progress = {});

/// worst.json: {format, figure, direction, value ("+inf"/"-inf" for an infinite figure, null when
/// the loop has none), status, parameters, unit_point, box, evaluations, sampled, starts, ...}.
nlohmann::json worst_machine_json(const WorstMachine& w);

/// Writes DIR/worst.json, DIR/worst.toml (the machine as a scene that analyse, sim and hil run)
/// and DIR/worst_model.toml. Returns the scene file.
std::string write_worst_machine(const WorstMachine& w, const std::string& out_dir);

}  // namespace flexloop::campaign
