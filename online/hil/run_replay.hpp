// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A hil run replayed in-process, sample for sample: the run's own plant and controller stations
// (online/loop/plant_station.hpp, controller_station.hpp) on a synthetic clock, from the start both
// processes drew, with the run's departures from the ideal loop as they were recorded -- the
// answers the plant did not apply (a deadline miss: it held its command or went safe) and the
// samples the controller did not answer (online/loop/sample_ranges.hpp). Every other answer is
// delivered in time. The replay is the loop the run was, timing included, so its RMS is what the
// run's should be: hil reports it beside sim's ideal loop, and the difference between the two is
// what the run's misses cost. A departure from the replay beyond rounding means the processes
// computed something else than the loop (a wrong message, a controller that is not
// deterministic).
// The replay runs on the general path (sized at start-up), the processes may run compiled
// kernels: the two agree to rounding, not bit for bit. Allocates, throws.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "artefact/loop_artefact.hpp"
#include "online/loop/loop_options.hpp"
#include "online/loop/sample_ranges.hpp"

namespace flexloop::hil {

/// What the run recorded (the plant's and the controller process's reports).
struct RunRecord {
  std::int64_t samples = 0;       ///< samples the plant took
  loop::SampleRanges unapplied;   ///< answers the plant did not apply, by seq
  loop::SampleRanges unanswered;  ///< samples the controller did not answer, by seq
};

/// The replay of `record` for `loop` run with the plant's options `o`:
///   {"performance_rms": [...], "command_rms": [...], "deadline_misses", "safe_command_cycles"}
/// or, when the record cannot be replayed, {"unavailable": why}.
nlohmann::json replay_run(const artefact::LoopArtefact& loop, const loop::LoopOptions& o,
                          const RunRecord& record);

}  // namespace flexloop::hil
