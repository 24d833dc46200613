// SPDX-License-Identifier: BSD-3-Clause
// `flexloop tradeoff SCENE [--methods ...] [--rates ...] [--forms ...] [--scalars ...]
//  [--reductions ...] [--orders ...] [--budget ERR] [--out-dir DIR]`
// What accuracy costs in time: the scene's plant over method x rate x form x scalar x model
// order (offline/study/tradeoff.hpp), printed as a table and written as tradeoff.csv,
// tradeoff.json and pareto_front.png in DIR.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/scene/scene.hpp"
#include "offline/scene/scene_plant.hpp"
#include "offline/study/tradeoff.hpp"
#include "offline/study/tradeoff_report.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {
namespace {

struct TradeoffArgs {
  std::string scene, out_dir = "out/tradeoff";
  study::TradeoffOptions options;
  double budget = 0;
  std::string cost = "step";
  bool quiet = false;
};

void run(TradeoffArgs& a) {
  const std::string dir = a.out_dir + "/";
  auto& reductions = a.options.reductions;
  if (reductions.size() == 1 && reductions[0] == "none") reductions.clear();
  a.options.cost = a.cost == "share" ? study::Cost::kShare : study::Cost::kStep;
  for (const char* f : {"tradeoff.csv", "tradeoff.json", "pareto_front.png"})
    common::require_writable(dir + f);
  const scene::ScenePlant p = scene::build_scene_plant(scene::load_scene(a.scene));
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  auto last = std::chrono::steady_clock::now() - std::chrono::hours(1);
  const auto start = std::chrono::steady_clock::now();
  if (!a.quiet)
    a.options.progress = [&](std::size_t done, std::size_t total, const study::Configuration& c) {
      const auto now = std::chrono::steady_clock::now();
      if (done < total && now - last < std::chrono::seconds(tty ? 1 : 10)) return;
      last = now;
      const double s = std::chrono::duration<double>(now - start).count();
      const double left = done > 0 ? s * static_cast<double>(total - done) / done : 0;
      std::fprintf(stderr, "%s[%zu/%zu] %s%s", tty ? "\r\033[K" : "", done, total,
                   done < total ? c.label().c_str() : "done",
                   done > 0 && done < total
                       ? (", ~" + std::to_string(static_cast<long>(left + 1)) + " s left").c_str()
                       : "");
      if (!tty || done == total) std::fprintf(stderr, "\n");
    };
  const study::TradeoffResult r = study::run_tradeoff(p, a.options);
  study::print_table(std::cout, r);
  study::write_csv(dir + "tradeoff.csv", r);
  nlohmann::json j = study::to_json(r);
  j["scene"] = a.scene;
  common::write_text_atomically(dir + "tradeoff.json", j.dump(1) + "\n");
  study::write_front_png(dir + "pareto_front.png", r, p.scene.name + ": accuracy against time");
  if (a.budget > 0) std::cout << study::budget_answer(r, a.budget) << "\n";
  std::cout << "wrote " << dir << "tradeoff.csv, tradeoff.json, pareto_front.png\n";
}

}  // namespace

void register_tradeoff(CLI::App& app) {
  auto args = std::make_shared<TradeoffArgs>();
  auto* cmd = app.add_subcommand(
      "tradeoff",
      "What accuracy costs in time: the scene's plant over discretisation method x rate x "
      "plant form x scalar x model order (modal and balanced truncation), each with its error "
      "against the exact continuous plant and the closed-loop step's time, measured in the "
      "same run; a table, CSV, JSON and the Pareto front as PNG");
  auto& o = args->options;
  cmd->add_option("scene", args->scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--methods", o.methods,
                  "zoh, foh, tustin, tustin-prewarp (at the lowest natural frequency), "
                  "backward-euler, euler")
      ->capture_default_str();
  cmd->add_option("--rates", o.rates_hz,
                  "Sample rates, Hz (default: the scene's / 10, / 2, x 1, x 2)")
      ->check(finite_range(1e-3, scene::kMaxLoopRateHz));
  cmd->add_option("--forms", o.forms, "dense, modal")->capture_default_str();
  cmd->add_option("--scalars", o.scalars, "double, float")->capture_default_str();
  cmd->add_option("--reductions", o.reductions,
                  "modal (truncation by contribution), modal-dc (with static correction), "
                  "balanced (SLICOT AB09MD); none: the full order only")
      ->capture_default_str();
  cmd->add_option("--orders", o.orders,
                  "Reduced orders, states (default: about 3/4, 1/2 and 1/4 of the full order)");
  cmd->add_option("--band", o.band_hz,
                  "Top of the error band, Hz (default: 2 x the highest natural frequency; "
                  "never above Nyquist)")
      ->check(finite_positive());
  cmd->add_option("--run", o.run_s, "Simulated seconds of the step and closed-loop runs")
      ->check(finite_range(1e-6, 60))
      ->capture_default_str();
  cmd->add_option("--bench-steps", o.bench_steps, "Closed-loop steps per timing repeat")
      ->check(CLI::Range(100L, 100'000'000L))
      ->capture_default_str();
  cmd->add_option("--repeats", o.repeats, "Timing repeats (median and spread)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--budget", args->budget,
                  "Relative H-inf error budget: print the cheapest configuration within it and "
                  "what it saves against the scene's own")
      ->check(finite_positive());
  cmd->add_option("--cost", args->cost,
                  "What the front and the budget call cost: step (ns per closed-loop step) or "
                  "share (of the sample period: the time x the rate)")
      ->check(CLI::IsMember({"step", "share"}))
      ->capture_default_str();
  cmd->add_option("--out-dir", args->out_dir,
                  "Directory for tradeoff.csv, tradeoff.json, "
                  "pareto_front.png")
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", args->quiet, "No progress on stderr");
  cmd->footer(
      "Errors (relative; the worst input-output pair or output): H-inf of the discrete response "
      "in the band against the exact plant as the loop drives it (the floor's columns against "
      "the continuous G(jw), the actuators' behind their zero-order hold); DC; an open-loop unit "
      "step on every input and the closed loop on the scene's floor, each against the full model "
      "by exact ZOH in double at the same rate (loop err: RMS of the difference; loop RMS: of the "
      "RMS). Time: the closed-loop step (plant + controller) on the kernels sim would use, "
      "median of the round-robin passes. Measure alone: a build or a second run beside it skews "
      "the times. doc/tradeoff.md has the details.\n"
      "Example:\n  flexloop tradeoff tools/scenes/metrology_frame.toml --budget 1e-2\n"
      "  flexloop tradeoff tools/scenes/flexible_arm.toml --band 500 --methods zoh foh tustin "
      "--rates 5000 10000 --reductions modal-dc balanced --orders 16 30 60 --budget 2e-2\n"
      "  flexloop tradeoff tools/scenes/metrology_frame.toml --methods zoh tustin --rates 2000 "
      "10000 --reductions none --cost share --out-dir out/small");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
