// SPDX-License-Identifier: BSD-3-Clause
#include "offline/report/hil_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "offline/report/plot.hpp"
#include "plant/lti/state_space_json.hpp"

namespace flexloop::report {

namespace {

constexpr int kPlotBins = 120;

// Rebins [[lower, upper, count], ...] into kPlotBins log-spaced bins in microseconds.
void plot_bins(const nlohmann::json& bins, const std::string& title, const std::string& png) {
  if (!bins.is_array() || bins.empty()) return;
  const double lo = std::max(0.1, bins.front()[0].get<double>() / 1e3);
  const double hi = std::max(lo * 1.01, bins.back()[1].get<double>() / 1e3 + 1e-3);
  std::vector<double> edges(kPlotBins + 1), counts(kPlotBins, 0.0);
  for (int i = 0; i <= kPlotBins; ++i) edges[i] = lo * std::pow(hi / lo, double(i) / kPlotBins);
  for (const auto& b : bins) {
    const double us = std::max(lo, b[0].get<double>() / 1e3);
    const int i = std::min(kPlotBins - 1,
                           static_cast<int>(kPlotBins * std::log(us / lo) / std::log(hi / lo)));
    counts[static_cast<std::size_t>(i)] += b[2].get<double>();
  }
  report::PlotSpec spec{
      title, "latency [\u00b5s], log scale", "cycles, log scale", true, true, 1000, 500};
  report::plot_histogram(spec, edges, counts, png);
}

// Microseconds with three significant digits and no exponent (8094, 58.4, 0.015).
std::string microseconds(double ns) {
  const double us = ns / 1e3;
  const int decimals = us >= 100 ? 0 : us >= 10 ? 1 : us >= 1 ? 2 : 3;
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, us);
  return text;
}

std::string figures(const nlohmann::json& s) {
  return "p50 " + microseconds(s.value("p50", 0.0)) + " / p99 " +
         microseconds(s.value("p99", 0.0)) + " / max " + microseconds(s.value("max", 0.0)) +
         " \u00b5s";
}

void print_line(const char* what, const nlohmann::json& s) {
  std::printf("  %-26s min %8.1f  p50 %8.1f  p99 %8.1f  p99.9 %8.1f  max %9.1f us\n", what,
              s.value("min", 0) / 1e3, s.value("p50", 0) / 1e3, s.value("p99", 0) / 1e3,
              s.value("p999", 0) / 1e3, s.value("max", 0) / 1e3);
}

double percent(double part, double whole) {
  return whole > 0 ? 100.0 * part / whole : 0.0;
}

// The same run's bare exchanges under the loop's round trip: the ping-pong on the loop's
// transport, the LCM one beside it (iceoryx runs), and the shared-memory floor under both.
void print_baseline_round_trips(const nlohmann::json& base) {
  const auto& pp = base["pingpong"];
  const std::string own = "  baseline " + pp.value("transport", std::string("lcm")) + " ping-pong";
  print_line(own.c_str(), pp["round_trip_ns"]);
  if (const auto lcm = base.find("pingpong_lcm"); lcm != base.end())
    print_line("  baseline lcm ping-pong", (*lcm)["round_trip_ns"]);
  if (const auto floor = base.find("shm_floor"); floor != base.end())
    print_line("  shared-memory floor", (*floor)["round_trip_ns"]);
}

}  // namespace

std::vector<std::string> write_hil_report(const nlohmann::json& report, const std::string& path) {
  nlohmann::json out = report;
  out.erase("histograms");
  if (const auto dir = std::filesystem::path(path).parent_path(); !dir.empty())
    std::filesystem::create_directories(dir);
  plant::lti::write_json_atomically(path, out);
  std::vector<std::string> written{path};
  if (!report.contains("histograms")) return written;
  const auto stem = std::filesystem::path(path).replace_extension("").string();
  const auto& h = report["histograms"];
  const auto& base = report["baseline"];
  char rate[64];
  std::snprintf(rate, sizeof rate, "%.6g kHz (%s, %s)", report.value("rate_hz", 0.0) / 1e3,
                report.value("wait_mode", "?").c_str(), report.value("receive_path", "?").c_str());
  const std::string rtt_png = stem + "_round_trip.png", late_png = stem + "_wakeup_lateness.png";
  plot_bins(h["round_trip_ns"],
            std::string("round trip at ") + rate + ": " + figures(report["round_trip_ns"]) +
                "\nbare " + base["pingpong"].value("transport", "lcm") + " ping-pong " +
                figures(base["pingpong"]["round_trip_ns"]),
            rtt_png);
  plot_bins(h["wakeup_lateness_ns"],
            std::string("plant wake-up lateness at ") + rate + ": " +
                figures(report["wakeup_lateness_ns"]) + "\nbare timer " +
                figures(base["timer"]["wakeup_lateness_ns"]),
            late_png);
  written.push_back(rtt_png);
  written.push_back(late_png);
  return written;
}

void print_physical(const nlohmann::json& r) {
  const auto p = r.find("physical");
  if (p == r.end() || !p->is_object()) return;
  const auto& perf = (*p)["performance"];
  const nlohmann::json& sim = p->contains("sim") ? (*p)["sim"] : nlohmann::json(nullptr);
  const bool own = sim.is_object() && sim["controller_on"].is_object();
  // The replay of this run's misses (online/hil/run_replay.hpp), when it could be made.
  const nlohmann::json& replay = p->contains("replay") ? (*p)["replay"] : nlohmann::json(nullptr);
  const bool replayed = replay.is_object() && replay.contains("performance_rms");
  std::printf("  RMS performance outputs, this run%s%s%s:\n",
              sim.is_object() ? " | sim, controller off" : "", own ? " | sim, controller on" : "",
              replayed ? " | sim with this run's misses" : "");
  for (std::size_t i = 0; i < perf.size(); ++i) {
    const double run = perf[i].value("rms", 0.0);
    std::printf("    %-14s %11.4e %s", perf[i].value("name", "?").c_str(), run,
                perf[i].value("unit", "").c_str());
    if (sim.is_object()) {
      const double off = sim["controller_off"]["performance_rms"][i].get<double>();
      std::printf(" | %11.4e (this run %+6.1f dB)", off, 20 * std::log10(run / off));
      if (own) {
        const double on = sim["controller_on"]["performance_rms"][i].get<double>();
        std::printf(" | %11.4e (%+6.1f dB)", on, 20 * std::log10(on / off));
      }
      if (replayed) {
        const double again = replay["performance_rms"][i].get<double>();
        std::printf(" | %11.4e (%+6.1f dB)", again, 20 * std::log10(again / off));
      }
    }
    std::printf("\n");
  }
  if (replayed) {
    double worst = 0;
    for (std::size_t i = 0; i < perf.size(); ++i)
      worst = std::max(
          worst,
          std::abs(perf[i].value("rms", 0.0) / replay["performance_rms"][i].get<double>() - 1));
    std::printf(
        "  sim with this run's %lld misses (%lld safe-command cycles), replayed sample for sample: "
        "largest |RMS this run / replay - 1| = %.1e\n",
        replay.value("deadline_misses", 0LL), replay.value("safe_command_cycles", 0LL), worst);
  } else if (replay.is_object()) {
    std::printf("  no replay of this run's misses: %s\n",
                replay.value("unavailable", std::string("?")).c_str());
  }
  double largest = 0;
  for (const auto& c : (*p)["command"]) largest = std::max(largest, c.value("rms", 0.0));
  std::printf("  RMS command (largest channel) %.4g, saturated in %.3f %% of the periods\n",
              largest, 100 * p->value("saturated_share", 0.0));
}

void print_verdict(const nlohmann::json& r) {
  const auto v = r.find("verdict");
  if (v == r.end() || !v->is_object()) return;
  std::printf("verdict: %s", v->value("result", "?").c_str());
  if (r.value("partial", false)) std::printf(" (partial: %lld cycles ran)", r.value("cycles", 0LL));
  if (const auto judged = v->find("judged"); judged != v->end() && judged->is_string())
    std::printf(", judged on %s", judged->get<std::string>().c_str());
  for (const auto& reason : v->value("reasons", std::vector<std::string>{}))
    std::printf("\n  - %s", reason.c_str());
  std::printf("\n");
}

namespace {

// The per-segment comparison with the interleaved baselines (online/hil/interleaved_baselines.hpp).
void print_segment_ratios(const nlohmann::json& r) {
  const auto b = r.find("baseline_ratios");
  if (b == r.end() || !b->is_object() || !(*b)["round_trip_p99_ratio"].is_object()) return;
  const auto& ratio = (*b)["round_trip_p99_ratio"];
  const auto& excess = (*b)["miss_share_minus_unanswered"];
  std::printf(
      "  against the baseline segment before each of %zu loop segments: round-trip p99 / "
      "ping-pong p99 median %.2f (%.2f .. %.2f); miss share - unanswered share median %+.3f %% "
      "(%+.3f .. %+.3f %%); %d of %zu segments within the timing tests' margins\n",
      (*b)["segments"].size(), ratio.value("median", 0.0), ratio.value("min", 0.0),
      ratio.value("max", 0.0), 100 * excess.value("median", 0.0), 100 * excess.value("min", 0.0),
      100 * excess.value("max", 0.0), b->value("segments_within_margins", 0),
      (*b)["segments"].size());
}

}  // namespace

void print_hil_summary(const nlohmann::json& r) {
  const double cycles = r.value("cycles", 0.0);
  const auto& pp = r["baseline"]["pingpong"];
  const bool own_controller = r["controller"].value("kind", "") != "none";
  std::printf("hil: %s at %.6g Hz for %.6g s over %s, wait %s, receive %s, plant CPU %d, %s%s\n",
              r.value("scene", "?").c_str(), r.value("rate_hz", 0.0), r.value("duration_s", 0.0),
              r.value("transport", "lcm").c_str(), r.value("wait_mode", "?").c_str(),
              r.value("receive_path", "?").c_str(), r.value("cpu", -1),
              own_controller
                  ? ("controller CPU " + std::to_string(r.value("controller_cpu", -1))).c_str()
                  : "no controller process",
              r.value("fifo", false) ? ", SCHED_FIFO" : ", SCHED_FIFO NOT granted");
  // The plant alone (no controller process, no answer came): no answers were expected, so
  // nothing about them is shown -- not 100 % deadline misses, not empty round trips.
  const bool open_loop = r.value("open_loop", false);
  const auto& controller = r["controller"];
  if (open_loop) {
    std::printf(
        "  open loop: the plant alone (controller type \"none\", and no process answered): no "
        "answers expected, no deadline misses judged\n");
    std::printf(
        "  cycles %lld, overruns %lld, skipped periods %lld, safe-command cycles %lld (the zero "
        "command held)\n",
        r.value("cycles", 0LL), r.value("overruns", 0LL), r.value("skipped_periods", 0LL),
        r.value("safe_command_cycles", 0LL));
    std::printf("  dropped messages: plant %s\n", r["dropped_messages"].dump().c_str());
  } else {
    if (controller.value("kind", "") == "none")
      std::printf(
          "  controller type \"none\": an external process answered %lld samples; its deadline "
          "misses are shown, not judged\n",
          controller.value("external_answers", 0LL));
    std::printf(
        "  cycles %lld, deadline misses %lld (%.3f %%), late answers %lld, overruns %lld, "
        "safe-command cycles %lld\n",
        r.value("cycles", 0LL), r.value("deadline_misses", 0LL),
        percent(r.value("deadline_misses", 0.0), cycles), r.value("late_answers", 0LL),
        r.value("overruns", 0LL), r.value("safe_command_cycles", 0LL));
    std::printf("  dropped messages: plant %s, controller %s\n",
                r["dropped_messages"].dump().c_str(),
                controller["dropped_messages"].dump().c_str());
    print_line("round trip", r["round_trip_ns"]);
    print_baseline_round_trips(r["baseline"]);
  }
  print_line("wake-up lateness", r["wakeup_lateness_ns"]);
  print_line("  baseline bare timer", r["baseline"]["timer"]["wakeup_lateness_ns"]);
  print_line("plant compute (TET)", r["plant_compute_ns"]);
  if (!open_loop) {
    print_line("controller compute", r["controller_compute_ns"]);
    // What the controller process watched of the controller (online/loop/real_time_promises.hpp).
    if (const auto p = controller.find("real_time_promises");
        p != controller.end() && p->contains("summary"))
      std::printf("  controller's %s\n", (*p)["summary"].get<std::string>().c_str());
    for (const char* key : {"pingpong", "pingpong_lcm"})
      if (const auto b = r["baseline"].find(key); b != r["baseline"].end())
        std::printf(
            "  baseline %s ping-pong: %lld of %lld pings unanswered within the period (%.3f %%)\n",
            b->value("transport", std::string("lcm")).c_str(), b->value("unanswered", 0LL),
            b->value("sent", 0LL), percent(b->value("unanswered", 0.0), b->value("sent", 0.0)));
  }
  const auto& timer = r["baseline"]["timer"];
  if (pp.value("too_short", false) || timer.value("too_short", false))
    std::printf(
        "  WARNING: baselines too short to compare with (%lld pings, %lld timer cycles; each "
        "needs %lld): lengthen --baseline-duration\n",
        pp.value("sent", 0LL), timer.value("cycles", 0LL), pp.value("min_samples", 0LL));
  if (!open_loop) print_segment_ratios(r);  // round trips against the ping-pong's: none here
  print_physical(r);
  if (const auto log = r.find("lcm_log"); log != r.end() && log->is_object())
    std::printf("  LCM log %s: %lld messages, %lld lost\n", log->value("path", "?").c_str(),
                log->value("messages", 0LL), log->value("dropped", 0LL));
  print_verdict(r);
}

void print_sweep_table(const std::vector<nlohmann::json>& reports) {
  std::printf(
      "\n| rate | wait | receive | cycles | misses | misses, ping-pong | round trip p50 / p99 / "
      "p99.9 [us] | ping-pong p50 / p99 / p99.9 [us] | p99 ratio (segment median) | timer lateness "
      "p99 [us] | "
      "verdict |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& r : reports) {
    const auto& rtt = r["round_trip_ns"];
    const auto& pp = r["baseline"]["pingpong"];
    const auto& ppr = pp["round_trip_ns"];
    // The median over the interleaved segments when there are any, else the whole-run ratio.
    const auto segmented = r.find("baseline_ratios");
    const double ratio = segmented != r.end() && (*segmented)["round_trip_p99_ratio"].is_object()
                             ? (*segmented)["round_trip_p99_ratio"].value("median", 0.0)
                         : ppr.value("p99", 0.0) > 0 ? rtt.value("p99", 0.0) / ppr.value("p99", 0.0)
                                                     : 0.0;
    std::printf(
        "| %.6g kHz | %s | %s | %lld | %lld (%.2f %%) | %lld (%.2f %%) | %.1f / %.1f / %.1f "
        "| %.1f / %.1f / %.1f | %.2f | %.1f | %s |\n",
        r.value("rate_hz", 0.0) / 1e3, r.value("wait_mode", "?").c_str(),
        r.value("receive_path", "?").c_str(), r.value("cycles", 0LL),
        r.value("deadline_misses", 0LL),
        percent(r.value("deadline_misses", 0.0), r.value("cycles", 0.0)),
        pp.value("unanswered", 0LL), percent(pp.value("unanswered", 0.0), pp.value("sent", 0.0)),
        rtt.value("p50", 0) / 1e3, rtt.value("p99", 0) / 1e3, rtt.value("p999", 0) / 1e3,
        ppr.value("p50", 0) / 1e3, ppr.value("p99", 0) / 1e3, ppr.value("p999", 0) / 1e3, ratio,
        r["baseline"]["timer"]["wakeup_lateness_ns"].value("p99", 0) / 1e3,
        r.contains("verdict") ? r["verdict"].value("result", "?").c_str() : "?");
  }
}

}  // namespace flexloop::report
