// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The controller process (`flexloop controller`, doc/design.md §7): answers each sensor message
// with the PI step (online/loop/controller_station.hpp) and publishes the actuator message, stamped
// with its send time and the step's compute time. Set-up as the plant's (pin, mlockall,
// prefaulted stack, SCHED_FIFO when permitted, /dev/cpu_dma_latency at 0), the PI controller
// sampled at the loop's rate (pass the plant's --rate). Waiting for a sample: block (sleep),
// hybrid (sleep until spin_margin before the next sample is due, then poll) or poll (spin).
// Runs until SIGINT / SIGTERM (or duration_s > 0 elapsed). Per message: no allocation, no
// exception; system calls over LCM: ppoll, read, sendmsg; over iceoryx none while it spins
// (a futex wait in block mode).
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "artefact/loop_artefact.hpp"
#include "online/loop/loop_options.hpp"
#include "online/loop/real_time_promises.hpp"
#include "online/loop/sample_ranges.hpp"
#include "rt/latency_histogram.hpp"
#include "rt/message_validation.hpp"

namespace flexloop::loop {

struct ControllerLoopResult {
  std::unique_ptr<rt::LatencyHistogram> compute = std::make_unique<rt::LatencyHistogram>();
  /// Sample received -> answer sent, ns (handling, step and encode in this process).
  std::unique_ptr<rt::LatencyHistogram> response = std::make_unique<rt::LatencyHistogram>();
  std::int64_t answered = 0;
  std::int64_t superseded = 0;  ///< samples replaced by a newer one before answered
  std::int64_t resyncs = 0;     ///< plant restarts followed
  std::int64_t resumes = 0;     ///< bumpless restarts after the plant went safe
  std::int64_t followed = 0;    ///< samples whose held command was not the last answer
  std::int64_t publish_failures = 0;
  /// A controller FMU's first call that ended its run (fmi2Discard, fmi2Error, fmi2Fatal,
  /// fmi2Pending), with its sample; empty while none has (from then on the process answered with
  /// the safe command, zero force). What the controller reported (loop_controller.hpp).
  std::string controller_failure;
  long controller_warnings = 0;               ///< calls that returned fmi2Warning
  std::string first_warning;                  ///< the first of them, with the FMU's message
  std::int64_t controller_messages = 0;       ///< the FMU's log messages (written to stderr)
  std::int64_t controller_messages_lost = 0;  ///< not kept: its log ring was full
  /// Allocations made while answering (rt/thread_allocations.hpp), in all answers and the
  /// answers that made any; 0 where the program does not count (allocations_counted false).
  std::int64_t allocations = 0;
  std::int64_t answers_allocating = 0;
  bool allocations_counted = false;
  std::int64_t period_ns = 0;
  /// The samples of the plant run it answered that it did not answer (superseded, dropped, or
  /// sent while it was stopped), by seq; incomplete when it answered more than one plant run.
  SampleRanges unanswered;
  rt::DropCounts drops;
  std::string setup;
  bool fifo = false;
};

/// Runs the artefact's controller until stopped (options.loop_path and rate_hz unused). `ready`
/// (optional) is called once LCM is subscribed and the process is set up, before the first
/// message is awaited. Errors before the loop: std::runtime_error / flexloop::InputError (also
/// for an artefact without a controller).
ControllerLoopResult run_controller_loop(const LoopOptions& options,
                                         const artefact::LoopArtefact& loop,
                                         const std::function<void()>& ready = {});

/// The process's counts, times, and which real-time promises the controller kept
/// ("real_time_promises", online/loop/real_time_promises.hpp).
nlohmann::json controller_result_json(const ControllerLoopResult& r, const LoopOptions& o);

/// What the process watched of the controller (real_time_promises.hpp).
AnswerWatch answer_watch(const ControllerLoopResult& r);

}  // namespace flexloop::loop
