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

BaselineSettings baseline_settings(const HilOptions& o, double rate_hz, double segment_s) {
  return {.clock = clock_options(o.loop, rate_hz),
          .receive_path = o.loop.receive_path,
          .realtime = o.loop.realtime,
          .pong_cpu = o.controller_cpu,
          .url = neighbour_port_url(loop::loop_lcm_url(o.loop.url, o.loop.link)),
          .segment_s = segment_s};
}

}  // namespace

nlohmann::json run_baselines(const HilOptions& o, double rate_hz) {
  InterleavedBaselines b(baseline_settings(o, rate_hz, o.baseline_duration_s));
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

}  // namespace

nlohmann::json run_hil(const HilOptions& o, const artefact::LoopArtefact& loop) {
  prepare_hil_network(o);
  // SIGINT / SIGTERM: this process forwards the stop to the plant, and the run ends with the
  // figures of what ran (a Ctrl-C reaches every process of the terminal's group anyway).
  loop::install_stop_handlers();
  // Both processes start from the one artefact.
  const std::string url = loop::loop_lcm_url(o.loop.url, o.loop.link);
  // A loop without a controller runs the plant alone: it publishes every sample and, with no
  // answer, holds and then applies the zero command (what an external controller would answer).
  const bool has_controller = loop.controller != artefact::ControllerKind::kNone;
  const loop::SharedLoopStatus status;
  loop::LoopOptions plant_options = o.loop;
  plant_options.url = url;
  plant_options.quiet = true;
  plant_options.status = status.get();
  plant_options.limits.judge_misses = has_controller;
  plant_options.lcm_log = o.lcm_log;  // the plant records what it sends and receives
  loop::LoopOptions controller_options = plant_options;
  controller_options.realtime.cpu = o.controller_cpu;
  controller_options.duration_s = 0;         // until stopped, after the plant
  controller_options.status = status.get();  // it writes only the sample in hand there

  // A1 B1 A2 B2 ...: baseline segments interleaved with the loop's (interleaved_baselines.hpp).
  const double duration_s = o.loop.duration_s > 0 ? o.loop.duration_s : loop.duration_s;
  const int segments = hil_segments(o, duration_s);
  const double baseline_s = o.baseline_duration_s > 0 ? o.baseline_duration_s : duration_s;
  plant_options.segments = segments;
  // Too short a segment compares noise with noise (and a baseline needs a whole period).
  constexpr double kMinSegmentPeriods = 100;
  const double shortest_s = std::min(duration_s, baseline_s) / segments;
  if (shortest_s * loop.rate_hz < kMinSegmentPeriods) {
    const auto g = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.6g", v);
      return std::string(text);
    };
    throw common::InputError("--segments", std::to_string(segments) + " segments of a " +
                                               g(duration_s) + " s run with " + g(baseline_s) +
                                               " s of baselines at " + g(loop.rate_hz) +
                                               " Hz leave fewer than " + g(kMinSegmentPeriods) +
                                               " periods per segment; use fewer");
  }
  const rt::CpuDmaLatencyHold dma;  // for the baselines (each loop process holds its own)
  nlohmann::json report;
  InterleavedBaselines baselines(baseline_settings(o, loop.rate_hz, baseline_s / segments));
  baselines.measure_segment();
  const auto interrupted_before_loop = [] {
    return loop::VerdictFailure{130, "interrupted before the loop ran: nothing was written"};
  };
  if (loop::stop_requested()) throw interrupted_before_loop();

  std::unique_ptr<ChildProcess> controller;
  if (has_controller) {
    controller = std::make_unique<ChildProcess>([&](const ChildLink& link) {
      return loop::controller_result_json(
                 loop::run_controller_loop(controller_options, loop, link.ready),
                 controller_options)
          .dump();
    });
    controller->wait_ready(10 * rt::kNsPerSecond);
  }
  ChildProcess plant([&](const ChildLink& link) {
    loop::LoopOptions options = plant_options;
    options.between_segments = link.pause;
    return loop::plant_result_json(loop::run_plant_loop(options, loop), options, true).dump();
  });
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
  StatusLine line(*status.get(), loop.rate_hz, o.status_line, has_controller);
  const auto watch = [&] {
    // Repeated while the stop stands: a stop that came before the plant installed its own
    // handlers is not lost.
    if (loop::stop_requested()) plant.signal(SIGTERM);
    line.tick();
  };
  const auto grace = static_cast<std::int64_t>((duration_s + 30) * 1e9);
  nlohmann::json plant_json;
  try {
    plant_json = nlohmann::json::parse(plant.finish(grace, watch, between_segments));
    line.finish();
  } catch (...) {
    line.finish();
    if (controller) controller->signal(SIGTERM);
    if (loop::stop_requested()) throw interrupted_before_loop();
    throw;
  }
  loop::RunVerdict verdict = loop::verdict_from_json(plant_json["verdict"]);
  nlohmann::json controller_json = {{"kind", "none"},
                                    {"dropped_messages", nlohmann::json::object()}};
  if (controller) {
    controller->signal(SIGTERM);
    try {
      controller_json = nlohmann::json::parse(controller->finish(10 * rt::kNsPerSecond));
    } catch (const std::exception& e) {
      // Its failure fails the run; the plant's figures are still reported.
      const std::string what = controller_process_failure(*controller, *status.get(), e);
      controller_json = {{"error", what}, {"dropped_messages", nlohmann::json::object()}};
      loop::add_failure(verdict, what);
    }
    controller_json["kind"] = artefact::to_string(loop.controller);
    if (const auto f = controller_json.find("controller_failure");
        f != controller_json.end() && f->is_string())
      loop::add_failure(verdict, "the controller FMU failed: " + f->get<std::string>() +
                                     "; its process answered with the safe command (zero "
                                     "force) from then on, which the plant applied");
  }

  report["baseline"] = baselines.totals_json();
  report.update(plant_json);
  report["baseline_ratios"] = baselines.comparison_json(plant_json["segments"]);
  // Misses above the limit where the bare ping-pong, in the same segments, lost as large a share:
  // the machine could not hold the rate, whatever the loop did. Said beside the failure.
  const auto& pp = report["baseline"]["pingpong"];
  const double unanswered_share =
      pp.value("sent", 0.0) > 0 ? pp.value("unanswered", 0.0) / pp.value("sent", 0.0) : 0.0;
  const auto loop_cycles = plant_json.value("cycles", std::int64_t{0});
  if (verdict.result == loop::RunVerdict::Result::kFail && plant_options.limits.judge_misses &&
      loop_cycles > 0 &&
      plant_json.value("deadline_misses", 0.0) / loop_cycles >
          plant_options.limits.max_miss_share &&
      unanswered_share > plant_options.limits.max_miss_share) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the bare LCM ping-pong, interleaved with the loop, left %.3g %% of its pings "
                  "unanswered as well: this machine did not hold %.6g Hz during the run",
                  100 * unanswered_share, loop.rate_hz);
    verdict.reasons.push_back(text);
  }
  // A controller that crashed its process would crash this one in sim's loop (the same code).
  const bool crashed = controller && !controller->killed_by().empty();
  if (report.contains("physical") && loop_cycles > 0 && crashed) {
    report["physical"]["sim_unavailable"] = "the controller process was killed by " +
                                            controller->killed_by() +
                                            ": its code is not run again in this process";
  } else if (report.contains("physical") && loop_cycles > 0) {
    report["physical"]["sim"] =
        sim_prediction(loop, static_cast<double>(loop_cycles) / loop.rate_hz);
    if (controller && plant_json["divergence"].is_string())
      report["physical"]["replay"] = {{"unavailable", "the run diverged"}};
    else if (controller && controller_json.contains("unanswered_samples"))
      report["physical"]["replay"] = replay_run(
          loop, plant_options,
          {.samples = plant_json.value("samples", std::int64_t{0}),
           .unapplied = loop::SampleRanges::from_json(plant_json["unapplied_answers"]),
           .unanswered = loop::SampleRanges::from_json(controller_json["unanswered_samples"])});
  }
  report["verdict"]["result"] = to_string(verdict.result);
  report["verdict"]["reasons"] = verdict.reasons;
  if (!has_controller) {
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
  } else {
    report["open_loop"] = false;
  }
  report["controller"] = controller_json;
  report["scene"] = o.loop.loop_path;
  report["duration_s"] = duration_s;
  report["controller_cpu"] = o.controller_cpu;
  report["lcm_url"] = url;
  report["cpu_dma_latency_held"] = dma.active();
  return report;
}

}  // namespace flexloop::hil
