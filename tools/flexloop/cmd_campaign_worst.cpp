// SPDX-License-Identifier: BSD-3-Clause
// `flexloop campaign worst SCENE -u U.toml --figure F --out-dir DIR` (issue 54, 3.3;
// doc/campaign.md "The worst machine in the box"): the machine of the parameters' box whose
// figure is worst, by a bounded derivative-free search from the worst sampled machines
// (offline/campaign/worst_machine.hpp); writes DIR/worst.json and DIR/worst.toml.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "offline/campaign/local_engine.hpp"
#include "offline/campaign/worst_machine.hpp"
#include "tools/flexloop/process_heap.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {
namespace {

using namespace flexloop::campaign;

struct WorstArgs {
  WorstRequest request;
  std::string out_dir;
  bool quiet = false;
};

// Progress with an ETA on stderr once the search has run 2 s (a short one stays quiet): one
// line rewritten on a terminal, a line every 10 s otherwise.
WorstProgress progress_printer(bool quiet) {
  if (quiet) return {};
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last = std::make_shared<double>(0.0);
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  return [=](long done, long total) {
    const double s = std::chrono::duration<double>(clock::now() - start).count();
    if (s < 2 || (s - *last < (tty ? 0.25 : 10) && done < total)) return;
    *last = s;
    std::fprintf(stderr, tty ? "\rworst: %s" : "worst: %s\n",
                 progress_text(done, total, s).c_str());
    if (tty && done == total) std::fputc('\n', stderr);
  };
}

void print_result(const WorstMachine& w, const std::string& scene_file) {
  const nlohmann::json j = worst_machine_json(w);
  std::printf(
      "worst %s: %s (status %s) after %ld machines (%ld sampled, %zu local searches); "
      "the worst sampled: %s\n",
      w.figure.name.c_str(), j["value"].dump().c_str(), j["status"].get<std::string>().c_str(),
      w.evaluations, w.sampled, w.starts.size(), j["worst_sampled_value"].dump().c_str());
  for (const auto& [path, value] : w.values) std::printf("  %s = %.9g\n", path.c_str(), value);
  std::printf("wrote %s and worst.json beside it\n", scene_file.c_str());
}

}  // namespace

void register_campaign_worst(CLI::App* campaign) {
  auto a = std::make_shared<WorstArgs>();
  a->request.plan.n = 64;
  auto* cmd = campaign->add_subcommand(
      "worst",
      "Search the parameters' box for the worst machine (largest spectral radius, peak sigma "
      "or RMS; smallest disk margin), each machine re-linearised from the FE model: sampled "
      "machines, then a bounded derivative-free search (NLopt BOBYQA) from the worst of them");
  cmd->add_option("scene", a->request.plan.scene, "Scene file (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--uncertain,-u", a->request.plan.uncertain, "Uncertain parameters (U.toml)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--figure", a->request.figure,
                  "spectral_radius, largest_inner_radius, disk_margin_db, peak_sigma, rms (one "
                  "performance channel) or rms.<channel>")
      ->capture_default_str();
  cmd->add_option("-n", a->request.plan.n, "Machines sampled first (Latin hypercube)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--seed", a->request.plan.seed, "Seed of the sampled machines")
      ->capture_default_str();
  cmd->add_option("--starts", a->request.starts, "Local searches, from the worst sampled")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--evaluations", a->request.evaluations,
                  "Machines the local searches may evaluate, shared between them")
      ->check(CLI::Range(0, 10000000))
      ->capture_default_str();
  cmd->add_option("--sigmas", a->request.sigmas,
                  "Non-uniform parameters span +-K standard deviations (default: their "
                  "quantiles 1e-6 .. 1 - 1e-6; uniform ones their bounds)")
      ->check(finite_positive());
  cmd->add_option("--controller", a->request.plan.controller, "frozen or redesigned")
      ->check(CLI::IsMember({"frozen", "redesigned"}));
  cmd->add_option("--out-dir", a->out_dir, "Directory for worst.json and worst.toml")->required();
  cmd->add_flag("--quiet,-q", a->quiet, "No progress on stderr");
  cmd->footer(
      "Example:\n  flexloop campaign worst tools/scenes/metrology_frame.toml -u "
      "tools/scenes/metrology_frame_uncertain.toml --figure disk_margin_db --out-dir out/worst\n"
      "  flexloop analyse out/worst/worst.toml");
  cmd->callback([a] {
    common::require_creatable(std::filesystem::path(a->out_dir) / "worst.json");
    keep_freed_memory();
    const WorstMachine w = find_worst_machine(a->request, progress_printer(a->quiet));
    print_result(w, write_worst_machine(w, a->out_dir));
  });
}

}  // namespace flexloop::cli
