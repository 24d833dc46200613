// SPDX-License-Identifier: BSD-3-Clause
// `flexloop hil SCENE --rate HZ --duration S --report OUT.json [--wait MODE] [--netns]
//  [--lcm-log FILE] [--sweep]`: the hardware-in-the-loop rehearsal (online/hil/hil_run.hpp):
// same-run baselines (bare timer, bare LCM ping-pong), then the controller and plant processes
// on the two cores for the duration; writes the report JSON and the round-trip and wake-up
// histograms (PNG) beside it, prints a summary. --sweep runs the rates 1, 2, 5, 10, 20 kHz
// (or --sweep-rates) one after another, writes OUT.json as {"sweep": [report, ...]} plus one
// PNG pair per rate, prints a Markdown table and the highest rate that held (it and every rate
// below it passed). --transport iceoryx: over shared memory, with the run's own RouDi and the
// iceoryx ping-pong as the baseline the loop is judged against. Without --netns it must run inside
// tools/netns-run (it refuses otherwise, exit 1).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "offline/report/hil_report.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/hil/hil_run.hpp"
#include "online/loop/run_verdict.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/loop_commands.hpp"
#include "tools/loop_cli/loop_options_cli.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

struct HilArgs : LoopArgs {
  std::string report;
  hil::HilOptions hil;
  bool sweep = false;
  bool quiet = false;
  std::vector<double> sweep_rates;  // empty: kSweepRates, and over iceoryx kFastSweepRates after
};

const std::vector<double> kSweepRates{1000, 2000, 5000, 10000, 20000};
const std::vector<double> kFastSweepRates{30000, 40000, 50000};

// The offline pipeline runs once per rate, here; the plant and controller start from its artefact.
artefact::LoopArtefact load_hil_loop(const hil::HilOptions& o) {
  return scene::load_loop(o.loop.loop_path,
                          {.rate_hz = o.loop.rate_hz, .form = std::nullopt, .duration_s = 0});
}

void print_written(const std::vector<std::string>& paths) {
  for (const auto& p : paths) std::printf("wrote %s\n", p.c_str());
}

// A loop that diverged (plant/runtime/divergence.hpp): its report is written (it says when and
// where), and the command fails.
void require_bounded(const nlohmann::json& report) {
  const auto d = report.find("divergence");
  if (d != report.end() && d->is_string()) throw std::runtime_error(d->get<std::string>());
}

void run_one(const HilArgs& a, hil::HilOptions o) {
  const nlohmann::json report = hil::run_hil(o, load_hil_loop(o));
  report::print_hil_summary(report);
  print_written(report::write_hil_report(report, a.report));
  require_bounded(report);
  loop::throw_unless_pass(loop::verdict_from_json(report["verdict"]));
}

// The highest rate of the sweep (run in rising order) below which every rate passed; 0: none.
double highest_rate_held(const std::vector<nlohmann::json>& reports) {
  double held = 0;
  for (const auto& r : reports) {
    if (loop::verdict_from_json(r["verdict"]).result != loop::RunVerdict::Result::kPass) break;
    held = r.value("rate_hz", 0.0);
  }
  return held;
}

void run_sweep(const HilArgs& a, hil::HilOptions o) {
  std::vector<nlohmann::json> reports;
  const auto stem = std::filesystem::path(a.report).replace_extension("").string();
  std::vector<double> rates = a.sweep_rates;
  if (rates.empty()) {
    rates = kSweepRates;
    if (o.loop.transport == rt::TransportKind::kIceoryx)
      rates.insert(rates.end(), kFastSweepRates.begin(), kFastSweepRates.end());
  }
  std::sort(rates.begin(), rates.end());
  for (const double rate : rates) {
    o.loop.rate_hz = rate;
    std::printf("\n--- %.6g Hz ---\n", rate);
    std::fflush(stdout);
    reports.push_back(hil::run_hil(o, load_hil_loop(o)));
    report::print_hil_summary(reports.back());
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_%.6ghz.json", rate);
    print_written(report::write_hil_report(reports.back(), stem + suffix));
    require_bounded(reports.back());
    if (loop::verdict_from_json(reports.back()["verdict"]).result ==
        loop::RunVerdict::Result::kInterrupted)
      break;  // the rates run so far are still tabled and written
  }
  nlohmann::json all = {{"sweep", nlohmann::json::array()}};
  for (auto r : reports) {
    r.erase("histograms");
    all["sweep"].push_back(r);
  }
  report::print_sweep_table(reports);
  const double held = highest_rate_held(reports);
  all["highest_rate_held_hz"] = held > 0 ? nlohmann::json(held) : nlohmann::json(nullptr);
  plant::lti::write_json_atomically(a.report, all);
  std::printf("wrote %s\n", a.report.c_str());
  if (held > 0)
    std::printf("\nhighest rate that held over %s: %.6g Hz (it and every rate below it passed)\n",
                a.transport.c_str(), held);
  else
    std::printf("\nno rate held over %s (the lowest failed)\n", a.transport.c_str());
  // The sweep runs every rate whatever each one's verdict; the worst decides the exit.
  loop::RunVerdict worst;
  for (const auto& r : reports) {
    const loop::RunVerdict v = loop::verdict_from_json(r["verdict"]);
    if (v.result == loop::RunVerdict::Result::kPass) continue;
    if (worst.result != loop::RunVerdict::Result::kInterrupted) worst.result = v.result;
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.6g Hz: ", r.value("rate_hz", 0.0));
    for (const auto& reason : v.reasons) worst.reasons.push_back(rate + reason);
  }
  loop::throw_unless_pass(worst);
}

void run(const HilArgs& a) {
  hil::HilOptions o = a.hil;
  o.loop = apply_loop_options(a);
  o.status_line = !a.quiet;
  common::require_writable(a.report);  // before the baselines and the run, not after them
  if (!o.lcm_log.empty()) common::require_writable(o.lcm_log);
  if (a.sweep)
    run_sweep(a, o);
  else
    run_one(a, o);
}

}  // namespace

void register_hil(CLI::App& app) {
  auto args = std::make_shared<HilArgs>();
  auto* cmd = app.add_subcommand("hil",
                                 "Hardware-in-the-loop rehearsal: baselines, then plant and "
                                 "controller processes over LCM or iceoryx");
  add_loop_options(cmd, *args, 0, kSceneOrArtefactHelp,
                   "hil starts iox-roudi for the run and stops it; refused when one already runs");
  add_safe_ramp_option(cmd, *args);
  add_verdict_options(cmd, *args);
  cmd->add_flag("--quiet", args->quiet,
                "No live status line (it is shown only when standard error is a terminal)");
  cmd->add_option("--duration", args->options.duration_s,
                  "Run time [s] (default: the scene's [run] duration)")
      ->check(finite_positive());
  cmd->add_option("--report", args->report,
                  "Report JSON; the histograms go beside it as <stem>_round_trip.png and "
                  "<stem>_wakeup_lateness.png")
      ->required();
  cmd->add_option("--controller-cpu", args->hil.controller_cpu,
                  "CPU of the controller process (--cpu is the plant's)")
      ->capture_default_str()
      ->check(CLI::Range(-1, 1023));
  cmd->add_option("--baseline-duration", args->hil.baseline_duration_s,
                  "Total length of each same-run baseline (timer, ping-pong) over all segments "
                  "[s] (default: the run's duration)")
      ->check(finite_range(0.01, 600.0));
  cmd->add_option("--segments", args->hil.segments,
                  "Interleave baseline and loop in this many segments, A1 B1 A2 B2 ... (default: "
                  "one per 2 s of the run, 1 to 5); each loop segment is compared with the "
                  "baseline measured just before it")
      ->check(CLI::Range(1, 100));
  cmd->add_flag("--netns", args->hil.netns,
                "Enter a private loopback-only network namespace first (as tools/netns-run)");
  cmd->add_option("--lcm-log", args->hil.lcm_log,
                  "Record every message the plant sends and receives, after the loop's channel "
                  "map, into this LCM log file (flexloop log FILE -o OUT.csv|.mat; replay: "
                  "lcm-logplayer-gui FILE)");
  cmd->add_flag("--sweep", args->sweep, "Run every rate of --sweep-rates and print a table");
  cmd->add_option("--sweep-rates", args->sweep_rates,
                  "Rates for --sweep [Hz] (default: 1, 2, 5, 10, 20 kHz; over iceoryx also 30, "
                  "40, 50 kHz)");
  cmd->footer(
      "Examples:\n"
      "  flexloop hil tools/scenes/metrology_frame.toml --rate 1000 --duration 10 --netns \\\n"
      "      --report out/hil/1khz.json\n"
      "  tools/netns-run -- flexloop hil tools/scenes/metrology_frame.toml --rate 10000 \\\n"
      "      --wait hybrid --duration 10 --report out/hil/10khz.json --lcm-log out/hil/run.lcmlog\n"
      "  flexloop hil tools/scenes/metrology_frame.toml --netns --sweep --duration 5 \\\n"
      "      --report out/hil/sweep.json\n"
      "  flexloop hil tools/scenes/metrology_frame.toml --netns --transport iceoryx --rate 20000 "
      "\\\n"
      "      --wait hybrid --duration 10 --report out/hil/20khz_iceoryx.json\n"
      "Exit: 0 pass; 3 verdict fail (deadline misses above --max-miss-share, stopped by "
      "--stop-after-misses, the controller process failed, the --lcm-log file could not be written "
      "or lost messages); 130 interrupted "
      "(SIGINT/SIGTERM: the report covers what ran, \"partial\": true); 1 also when the plant "
      "diverged (|[z; u]| > 1e12 or not finite). The report is written in each of these cases and "
      "says why (\"verdict\", \"divergence\"); --sweep runs every rate and exits with the "
      "worst.");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
