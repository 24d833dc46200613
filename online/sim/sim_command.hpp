// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What `flexloop sim` computes, apart from what it prints and writes (the command line and the
// Python module's flexloop.sim both call it, so both give the same bits): the two runs of a loop
// artefact with the log of the requested one, the judgement of the runs (a controller that could
// not complete its run, a loop that diverged), the log's column names and the RMS table.
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "online/sim/scene_runs.hpp"

namespace flexloop::sim {

struct SimRequest {
  /// Log the run with the controller on (a loop without a controller has only the off run).
  bool controller_on = true;
  StartKind start = StartKind::kStationary;
  bool general = false;  ///< the general path even where a compiled loop matches
  long log_every = 1;
  bool log = false;       ///< log the requested run
  bool log_both = false;  ///< log both runs (sim's plots)
  ProgressFactory progress;
  /// As SceneRunOptions::after_first_run (the logged run comes first).
  std::function<void(RunResult&)> after_first_run;
};

/// True when the logged run is the one with the controller on: requested, and the loop has one.
bool logs_controller_on(const artefact::LoopArtefact& a, const SimRequest& r);

/// The artefact's step and its duration in steps, logging every `log_every`-th sample.
RunSettings sim_settings(const artefact::LoopArtefact& a, long log_every);

/// Both runs (the logged one first). @throws flexloop::InputError for what the hardware or a
/// controller FMU refuses. The runs are not judged: require_completed.
BothRuns run_sim(const artefact::LoopArtefact& a, const SimRequest& r);

/// @throws std::runtime_error, as sim reports it, for a controller-on run its controller could
/// not complete (a controller FMU's fmi2Discard or fmi2Pending) and for a run that diverged:
/// their RMS values would be another loop's or meaningless.
void require_completed(const artefact::LoopArtefact& a, const BothRuns& r);

/// The log's columns: t_s, then per channel "<role> <name> [<unit>]" for the disturbances,
/// performance outputs, performance outputs as sensed, sensors and commands.
std::vector<std::string> log_header(const artefact::LoopArtefact& a);

/// One line of sim's RMS table: a performance output's RMS with the controller off and on, and
/// the change 20 log10(on / off) in dB (on and change NaN for a loop without a controller).
struct RmsRow {
  std::string channel, unit;
  double off = 0, on = 0, change_db = 0;
};
std::vector<RmsRow> rms_table(const artefact::LoopArtefact& a, const BothRuns& r);

}  // namespace flexloop::sim
