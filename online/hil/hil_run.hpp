// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `flexloop hil`: one hardware-in-the-loop rehearsal, measured against baselines taken in the
// same run (doc/design.md §7). In order:
//   1. the private network: with `netns`, enter a fresh loopback-only namespace in-process
//      (online/loop/private_network.hpp); otherwise the caller must already be in one
//      (tools/netns-run);
//   2. the loop artefact the caller built or read (both processes get it by fork);
//   3. baselines with the loop's rate, wait mode, CPUs and priority: a bare periodic thread on
//      the plant's CPU (rt/timer_baseline.hpp) and a bare LCM ping-pong between the plant's and
//      the controller's CPUs (rt/pingpong_baseline.hpp), in segments interleaved with the
//      loop's (online/hil/interleaved_baselines.hpp): the first here, the others while the loop
//      pauses between its segments;
//   4. the controller process (forked, online/loop/controller_loop.hpp), and once it has
//      subscribed, the plant process (forked, online/loop/plant_loop.hpp) for the duration; then
//      the controller is stopped (SIGTERM) and both hand back their figures. A loop without a
//      controller runs the plant alone (report "controller": {"kind": "none", "external_answers":
//      answers a user's own process sent}, "open_loop": true when none came). Meanwhile a live
//      status line (online/hil/status_line.hpp). With lcm_log, the plant process records what
//      it sends and receives (rt/event_log_recorder.hpp);
//   5. the verdict (online/loop/run_verdict.hpp): the plant's limits (a log that could not be
//      written, or lost messages, among them), and a controller process that failed fails the run.
//      Without a controller process the deadline misses are not judged (nobody is expected to
//      answer): the report's verdict "judged" says what was.
//      SIGINT / SIGTERM end the loop early; the report then covers what ran ("partial": true,
//      verdict "interrupted"). Before the loop ran, an interruption throws VerdictFailure (130) and
//      nothing is reported.
// The result is the report (keys of offline/report/hil_report.hpp), with the plant's histogram bins
// under "histograms" for drawing. Orchestration: allocates, throws std::runtime_error /
// flexloop::InputError.
#include <nlohmann/json.hpp>
#include <string>

#include "artefact/loop_artefact.hpp"
#include "online/loop/loop_options.hpp"

namespace flexloop::hil {

struct HilOptions {
  loop::LoopOptions loop;  ///< the plant's settings (realtime.cpu: the plant's CPU)
  int controller_cpu = 1;  ///< -1: not pinned
  /// Each baseline's total time (timer, ping-pong), over all segments; 0: the loop's duration.
  double baseline_duration_s = 0;
  /// Loop segments interleaved with baseline segments; 0: one per kAutoSegmentS of the run, at
  /// most kMaxAutoSegments, at least 1.
  int segments = 0;
  bool netns = false;       ///< enter a private namespace first
  std::string lcm_log;      ///< the plant records the run into this LCM log file
  bool status_line = true;  ///< a live status line on a terminal's standard error
};

inline constexpr double kAutoSegmentS = 2.0;
inline constexpr int kMaxAutoSegments = 5;

/// The number of segments a run of duration_s gets (HilOptions::segments, or the automatic one).
int hil_segments(const HilOptions& o, double duration_s);

/// Enters the private namespace when asked (once per process; later calls do nothing).
void prepare_hil_network(const HilOptions& o);

/// Step 3 alone, in one segment: the bare timer and ping-pong baselines at `rate_hz` with the
/// loop's wait mode, receive path, URL, CPUs and priority, each for `o.baseline_duration_s`
/// (> 0); the report's "baseline" object {timer, pingpong, segments}. Call prepare_hil_network
/// first.
nlohmann::json run_baselines(const HilOptions& o, double rate_hz);

/// Runs the rehearsal of `loop` (its rate; o.loop.loop_path names it in the report) and returns
/// the report (see the header comment).
nlohmann::json run_hil(const HilOptions& o, const artefact::LoopArtefact& loop);

}  // namespace flexloop::hil
