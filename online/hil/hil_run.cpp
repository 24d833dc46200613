// SPDX-License-Identifier: BSD-3-Clause
#include "online/hil/hil_run.hpp"

#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "common/input_error.hpp"
#include "online/hil/baseline_json.hpp"
#include "online/hil/child_process.hpp"
#include "online/hil/interleaved_baselines.hpp"
#include "online/hil/run_replay.hpp"
#include "online/hil/status_line.hpp"
#include "online/loop/controller_loop.hpp"
#include "online/loop/plant_loop.hpp"
#include "online/loop/private_network.hpp"
#include "online/loop/run_verdict.hpp"
#include "online/loop/stop_signal.hpp"
#include "online/sim/scene_runs.hpp"
#include "rt/loop_process_setup.hpp"
#include "rt/loop_transport.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/pingpong_baseline.hpp"
#include "rt/timer_baseline.hpp"

namespace flexloop::hil {

namespace {

rt::PeriodicClockOptions clock_options(const loop::LoopOptions& o, double rate_hz) {
  return {.period_ns = static_cast<std::int64_t>(1e9 / rate_hz + 0.5),
          .wait_mode = o.wait,
          .spin_margin_ns = o.spin_margin_ns};
}

BaselineSettings baseline_settings(const HilOptions& o, double rate_hz, double segment_s,
                                   rt::RoudiProcess* roudi) {
  return {.clock = clock_options(o.loop, rate_hz),
          .receive_path = o.loop.receive_path,
          .realtime = o.loop.realtime,
          .pong_cpu = o.controller_cpu,
          .url = neighbour_port_url(loop::loop_lcm_url(o.loop.url, o.loop.link)),
          .segment_s = segment_s,
          .transport = o.loop.transport,
          .roudi = roudi};
}

// iceoryx: the run's own RouDi, started by this process, which never registers with it (its
// children do: the loop's processes and the baselines' ping and pong); none over LCM.
std::unique_ptr<rt::RoudiProcess> start_roudi(const HilOptions& o) {
  if (o.loop.transport != rt::TransportKind::kIceoryx) return nullptr;
  return std::make_unique<rt::RoudiProcess>(rt::loop_roudi_options());
}

}  // namespace

nlohmann::json run_baselines(const HilOptions& o, double rate_hz) {
  const std::unique_ptr<rt::RoudiProcess> roudi = start_roudi(o);
  InterleavedBaselines b(baseline_settings(o, rate_hz, o.baseline_duration_s, roudi.get()));
  b.measure_segment();
  return b.totals_json();
}

int hil_segments(const HilOptions& o, double duration_s) {
  if (o.segments > 0) return o.segments;
  return static_cast<int>(std::clamp(std::floor(duration_s / kAutoSegmentS), 1.0,
                                     static_cast<double>(kMaxAutoSegments)));
}

void prepare_hil_network(const HilOptions& o) {
  static bool entered = false;
  if (o.netns && !entered) {
    loop::enter_private_loopback_namespace();
    entered = true;
  }
  loop::require_private_network("flexloop hil", o.loop.link);
}

namespace {

// What `flexloop sim` predicts for the same loop, seeds and duration: the RMS of each performance
// output with the controller off and (a loop with flexloop's own controller) on, and the RMS
// commands. With every answer in time the real-time run is the same loop sample for sample.
nlohmann::json sim_prediction(const artefact::LoopArtefact& loop, double duration_s) {
  sim::RunSettings s;
  s.dt = loop.dt();
  s.steps = std::lround(duration_s * loop.rate_hz);
  const sim::BothRuns r = sim::run_artefact(loop, s, {});
  const auto values = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.data(), v.data() + v.size());
  };
  nlohmann::json j = {{"controller_off", {{"performance_rms", values(r.off.rms_performance)}}},
                      {"controller_on", nullptr}};
  if (r.controlled)
    j["controller_on"] = {{"performance_rms", values(r.on.rms_performance)},
                          {"command_rms", values(r.on.rms_command)}};
  // A controller FMU that could not complete its run in sim either (fmi2Discard, fmi2Pending):
  // sim's loop held the safe command from there on, as the real-time run did.
  if (r.controlled && !r.on.controller.failure.empty())
    j["controller_on"]["controller_failure"] = r.on.controller.failure;
  return j;
}

// Why the controller process gave no result: killed by a signal (a crash in the controller's
// step: the sample it was answering, from the shared status), or its own error.
std::string controller_process_failure(const ChildProcess& c, const loop::LoopStatus& status,
                                       const std::exception& e) {
  if (c.killed_by().empty()) return std::string("the controller process failed: ") + e.what();
  const std::int64_t sample = status.controller_sample.load(std::memory_order_relaxed);
  return "controller process killed by " + c.killed_by() +
         (sample >= 0 ? " at sample " + std::to_string(sample) : " before its first answer") +
         "; the plant applied the safe command from then on";
}

// What the run is to do, fixed before anything starts: the settings each process gets and how
// the run is cut into segments.
struct HilPlan {
  std::string url;  // both processes start from the one artefact, on this LCM URL
  bool has_controller = false;
  loop::LoopOptions plant_options;
  loop::LoopOptions controller_options;
  double duration_s = 0;
  int segments = 1;
  double baseline_s = 0;  // the baselines' total time, over all segments
};

HilPlan plan_hil(const HilOptions& o, const artefact::LoopArtefact& loop,
                 loop::LoopStatus* status) {
  HilPlan p;
  p.url = loop::loop_lcm_url(o.loop.url, o.loop.link);
  // A loop without a controller runs the plant alone: it publishes every sample and, with no
  // answer, holds and then applies the zero command (what an external controller would answer).
  p.has_controller = loop.controller != artefact::ControllerKind::kNone;
  p.plant_options = o.loop;
  p.plant_options.url = p.url;
  p.plant_options.quiet = true;
  p.plant_options.status = status;
  p.plant_options.limits.judge_misses = p.has_controller;
  // Over iceoryx the plant waits for the controller's connection; alone, for nobody.
  if (!p.has_controller) p.plant_options.connect_timeout_s = 0;
  p.plant_options.lcm_log = o.lcm_log;  // the plant records what it sends and receives
  p.controller_options = p.plant_options;
  p.controller_options.realtime.cpu = o.controller_cpu;
  p.controller_options.duration_s = 0;   // until stopped, after the plant
  p.controller_options.status = status;  // it writes only the sample in hand there

  // A1 B1 A2 B2 ...: baseline segments interleaved with the loop's (interleaved_baselines.hpp).
  p.duration_s = o.loop.duration_s > 0 ? o.loop.duration_s : loop.duration_s;
  p.segments = hil_segments(o, p.duration_s);
  p.baseline_s = o.baseline_duration_s > 0 ? o.baseline_duration_s : p.duration_s;
  p.plant_options.segments = p.segments;
  return p;
}

// Too short a segment compares noise with noise (and a baseline needs a whole period).
void require_long_enough_segments(const HilPlan& p, double rate_hz) {
  constexpr double kMinSegmentPeriods = 100;
  const double shortest_s = std::min(p.duration_s, p.baseline_s) / p.segments;
  if (shortest_s * rate_hz < kMinSegmentPeriods) {
    const auto g = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.6g", v);
      return std::string(text);
    };
    throw common::InputError("--segments", std::to_string(p.segments) + " segments of a " +
                                               g(p.duration_s) + " s run with " + g(p.baseline_s) +
                                               " s of baselines at " + g(rate_hz) +
                                               " Hz leave fewer than " + g(kMinSegmentPeriods) +
                                               " periods per segment; use fewer");
  }
}

// A stop before the loop ran leaves no figures: nothing is reported, exit 130 (SIGINT's).
loop::VerdictFailure interrupted_before_loop() {
  return {130, "interrupted before the loop ran: nothing was written"};
}

// A child registered with RouDi leaves with exit(), so that iceoryx's runtime deregisters.
ChildEnd child_end(const HilPlan& p) {
  return p.plant_options.transport == rt::TransportKind::kIceoryx ? ChildEnd::kExit
                                                                  : ChildEnd::kImmediate;
}

// The run's RouDi (iceoryx), looked at while the loop runs: a RouDi that ended stops the run (the
// plant's figures so far are reported) and fails its verdict, naming how it ended.
class RoudiWatch {
 public:
  explicit RoudiWatch(rt::RoudiProcess* roudi) : roudi_(roudi) {}
  /// True on the first look that finds RouDi gone (and on every later one).
  bool lost_now() {
    if (roudi_ != nullptr && lost_.empty() && !roudi_->alive())
      lost_ = roudi_->describe() + " during the loop: the run was stopped there";
    return !lost_.empty();
  }
  const std::string& lost() const { return lost_; }

 private:
  rt::RoudiProcess* roudi_;
  std::string lost_;
};

// The controller process, once it has subscribed (so the plant's first sample finds it); none
// for a loop without a controller.
std::unique_ptr<ChildProcess> start_controller_process(const HilPlan& p,
                                                       const artefact::LoopArtefact& loop) {
  if (!p.has_controller) return nullptr;
  auto controller = std::make_unique<ChildProcess>(
      [&](const ChildLink& link) {
        return loop::controller_result_json(
                   loop::run_controller_loop(p.controller_options, loop, link.ready),
                   p.controller_options)
            .dump();
      },
      child_end(p));
  controller->wait_ready(10 * rt::kNsPerSecond);
  return controller;
}

// The plant process for the run's duration, its loop segments interleaved with the remaining
// baseline segments; its figures (JSON). On failure the controller is told to stop before the
// error goes on.
nlohmann::json run_plant_segments(const HilPlan& p, const artefact::LoopArtefact& loop,
                                  const loop::LoopStatus& status, bool status_line,
                                  InterleavedBaselines& baselines, ChildProcess* controller,
                                  RoudiWatch& roudi) {
  ChildProcess plant(
      [&](const ChildLink& link) {
        loop::LoopOptions options = p.plant_options;
        options.between_segments = link.pause;
        return loop::plant_result_json(loop::run_plant_loop(options, loop), options, true).dump();
      },
      child_end(p));
  // Between two loop segments: the plant waits, the controller process is stopped (SIGSTOP: it
  // neither spins nor reads), the next baseline segment runs on their CPUs.
  const auto between_segments = [&] {
    if (loop::stop_requested()) return;
    if (controller) controller->signal(SIGSTOP);
    try {
      baselines.measure_segment();
    } catch (...) {
      if (controller) controller->signal(SIGCONT);
      throw;
    }
    if (controller) controller->signal(SIGCONT);
  };
  StatusLine line(status, loop.rate_hz, status_line, p.has_controller);
  const auto watch = [&] {
    // Repeated while the stop stands: a stop that came before the plant installed its own
    // handlers is not lost.
    if (loop::stop_requested() || roudi.lost_now()) plant.signal(SIGTERM);
    line.tick();
  };
  const auto grace = static_cast<std::int64_t>((p.duration_s + 30) * 1e9);
  try {
    nlohmann::json plant_json = nlohmann::json::parse(plant.finish(grace, watch, between_segments));
    line.finish();
    return plant_json;
  } catch (...) {
    line.finish();
    if (controller) controller->signal(SIGTERM);
    if (loop::stop_requested()) throw interrupted_before_loop();
    throw;
  }
}

// Stops the controller process (the plant has finished) and takes its figures. Its failure, or
// its FMU's, fails the run; the plant's figures are still reported.
nlohmann::json collect_controller(ChildProcess* controller, const loop::LoopStatus& status,
                                  artefact::ControllerKind kind, loop::RunVerdict& verdict) {
  nlohmann::json controller_json = {{"kind", "none"},
                                    {"dropped_messages", nlohmann::json::object()}};
  if (!controller) return controller_json;
  controller->signal(SIGTERM);
  try {
    controller_json = nlohmann::json::parse(controller->finish(10 * rt::kNsPerSecond));
  } catch (const std::exception& e) {
    const std::string what = controller_process_failure(*controller, status, e);
    controller_json = {{"error", what}, {"dropped_messages", nlohmann::json::object()}};
    loop::add_failure(verdict, what);
  }
  controller_json["kind"] = artefact::to_string(kind);
  if (const auto f = controller_json.find("controller_failure");
      f != controller_json.end() && f->is_string())
    loop::add_failure(verdict, "the controller FMU failed: " + f->get<std::string>() +
                                   "; its process answered with the safe command (zero "
                                   "force) from then on, which the plant applied");
  return controller_json;
}

// Misses above the limit where the bare ping-pong, in the same segments, lost as large a share:
// the machine could not hold the rate, whatever the loop did. Said beside the failure.
void note_machine_could_not_hold_rate(loop::RunVerdict& verdict, nlohmann::json& report,
                                      const nlohmann::json& plant_json,
                                      const loop::RunLimits& limits, double rate_hz) {
  const auto& pp = report["baseline"]["pingpong"];
  const double unanswered_share =
      pp.value("sent", 0.0) > 0 ? pp.value("unanswered", 0.0) / pp.value("sent", 0.0) : 0.0;
  const auto loop_cycles = plant_json.value("cycles", std::int64_t{0});
  if (verdict.result == loop::RunVerdict::Result::kFail && limits.judge_misses && loop_cycles > 0 &&
      plant_json.value("deadline_misses", 0.0) / loop_cycles > limits.max_miss_share &&
      unanswered_share > limits.max_miss_share) {
    const bool iceoryx = pp.value("transport", "lcm") == "iceoryx";
    char text[200];
    std::snprintf(text, sizeof text,
                  "the bare %s ping-pong, interleaved with the loop, left %.3g %% of its pings "
                  "unanswered as well: this machine did not hold %.6g Hz during the run",
                  iceoryx ? "iceoryx" : "LCM", 100 * unanswered_share, rate_hz);
    verdict.reasons.push_back(text);
  }
}

// The physical section's predictions: sim's RMS for as many cycles as ran, and the replay of the
// recorded misses. A controller that crashed its process would crash this one in sim's loop (the
// same code): then neither.
void add_predictions(nlohmann::json& report, nlohmann::json& plant_json,
                     nlohmann::json& controller_json, const ChildProcess* controller,
                     const HilPlan& p, const artefact::LoopArtefact& loop) {
  const auto loop_cycles = plant_json.value("cycles", std::int64_t{0});
  if (!report.contains("physical") || loop_cycles <= 0) return;
  if (controller && !controller->killed_by().empty()) {
    report["physical"]["sim_unavailable"] = "the controller process was killed by " +
                                            controller->killed_by() +
                                            ": its code is not run again in this process";
    return;
  }
  report["physical"]["sim"] = sim_prediction(loop, static_cast<double>(loop_cycles) / loop.rate_hz);
  if (controller && plant_json["divergence"].is_string())
    report["physical"]["replay"] = {{"unavailable", "the run diverged"}};
  else if (controller && controller_json.contains("unanswered_samples"))
    report["physical"]["replay"] = replay_run(
        loop, p.plant_options,
        {.samples = plant_json.value("samples", std::int64_t{0}),
         .unapplied = loop::SampleRanges::from_json(plant_json["unapplied_answers"]),
         .unanswered = loop::SampleRanges::from_json(controller_json["unanswered_samples"])});
}

// The verdict's fields, and whether the loop ran open (no controller process, nobody answering).
void add_verdict(nlohmann::json& report, nlohmann::json& controller_json,
                 nlohmann::json& plant_json, const loop::RunVerdict& verdict, bool has_controller) {
  report["verdict"]["result"] = to_string(verdict.result);
  report["verdict"]["reasons"] = verdict.reasons;
  if (has_controller) {
    report["open_loop"] = false;
    return;
  }
  // No controller process: what ran is the plant alone, unless an external process answered
  // (a user's controller in the same namespace, doc/external_controller.md). Either way
  // nobody's misses are judged (RunLimits::judge_misses); the verdict says what it judged.
  const auto answers = plant_json["round_trip_ns"].value("count", std::int64_t{0});
  controller_json["external_answers"] = answers;
  report["open_loop"] = answers == 0;
  report["verdict"]["judged"] =
      "the plant's own run (divergence, its LCM log, the helper processes); not deadline "
      "misses: no controller process in this run" +
      std::string(answers == 0 ? ", and none answered (no answers expected)" : "");
}

}  // namespace

nlohmann::json run_hil(const HilOptions& o, const artefact::LoopArtefact& loop) {
  prepare_hil_network(o);
  // SIGINT / SIGTERM: this process forwards the stop to the plant, and the run ends with the
  // figures of what ran (a Ctrl-C reaches every process of the terminal's group anyway).
  loop::install_stop_handlers();
  const loop::SharedLoopStatus status;  // mapped before the forks: all three processes see it
  const HilPlan plan = plan_hil(o, loop, status.get());
  require_long_enough_segments(plan, loop.rate_hz);

  const rt::CpuDmaLatencyHold dma;  // for the baselines (each loop process holds its own)
  const std::unique_ptr<rt::RoudiProcess> roudi = start_roudi(o);
  InterleavedBaselines baselines(
      baseline_settings(o, loop.rate_hz, plan.baseline_s / plan.segments, roudi.get()));
  baselines.measure_segment();
  if (loop::stop_requested()) throw interrupted_before_loop();
  const std::unique_ptr<ChildProcess> controller = start_controller_process(plan, loop);
  RoudiWatch roudi_watch(roudi.get());
  nlohmann::json plant_json = run_plant_segments(plan, loop, *status.get(), o.status_line,
                                                 baselines, controller.get(), roudi_watch);

  loop::RunVerdict verdict = loop::verdict_from_json(plant_json["verdict"]);
  if (roudi_watch.lost_now()) {  // the stop was ours, not the user's: a failure, not a Ctrl-C
    verdict.result = loop::RunVerdict::Result::kFail;
    verdict.reasons.push_back(roudi_watch.lost());
  }
  nlohmann::json controller_json =
      collect_controller(controller.get(), *status.get(), loop.controller, verdict);
  nlohmann::json report;
  report["baseline"] = baselines.totals_json();
  report.update(plant_json);
  report["baseline_ratios"] = baselines.comparison_json(plant_json["segments"]);
  note_machine_could_not_hold_rate(verdict, report, plant_json, plan.plant_options.limits,
                                   loop.rate_hz);
  add_predictions(report, plant_json, controller_json, controller.get(), plan, loop);
  add_verdict(report, controller_json, plant_json, verdict, plan.has_controller);
  report["controller"] = controller_json;
  report["scene"] = o.loop.loop_path;
  report["duration_s"] = plan.duration_s;
  report["controller_cpu"] = o.controller_cpu;
  report["lcm_url"] = plan.url;
  report["transport"] = rt::to_string(o.loop.transport);
  report["cpu_dma_latency_held"] = dma.active();
  return report;
}

}  // namespace flexloop::hil
