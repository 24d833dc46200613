// SPDX-License-Identifier: BSD-3-Clause
// `flexloop campaign SCENE --uncertain U.toml -n N --out-dir DIR` and its parts for engines:
// `campaign plan`, `campaign run plan.json --shard K/M -o shard-K.jsonl`, `campaign submit
// plan.json --engine local|slurm`, `campaign report plan.json shard-*.jsonl --out-dir DIR`
// (issue 47, doc/campaign.md): every machine that will be built, sampled from the uncertain
// parameters of its FE model and scene, each judged as its sampled loop runs.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <thread>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/campaign_report.hpp"
#include "offline/campaign/local_engine.hpp"
#include "offline/campaign/plan_file.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/campaign/shard_merge.hpp"
#include "offline/campaign/shard_run.hpp"
#include "offline/campaign/slurm_engine.hpp"
#include "offline/campaign/subset_campaign.hpp"
#include "offline/campaign/worst_samples.hpp"
#include "tools/flexloop/process_heap.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {
namespace {

namespace fs = std::filesystem;
using namespace flexloop::campaign;

int all_cores() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

std::string this_program() {
  return fs::read_symlink("/proc/self/exe").string();
}

struct PlanArgs {
  PlanRequest request;
  std::string output = "plan.json";
};

struct RunArgs {
  std::string plan, shard = "0/1", output;
  bool quiet = false;
};

struct SubmitArgs {
  std::string plan, engine = "local", work_dir, partition, account;
  std::vector<std::string> sbatch_args;
  int shards = 0, jobs = all_cores(), array_throttle = 0;  // shards 0: the engine's default
  double time_limit_min = 60;
  bool quiet = false;
};

struct ReportArgs {
  std::string plan, out_dir;
  std::vector<std::string> shards;
  int worst = 5;
};

struct CampaignArgs {
  PlanRequest request;
  std::string scene, out_dir, method = "sampling", margin = "radius";
  int jobs = all_cores(), worst = 5;
  bool quiet = false;
};

void write_plan(const nlohmann::json& plan, const std::string& path) {
  common::require_writable(path);
  common::write_text_atomically(path, plan.dump(1) + "\n");
  const std::string simulated =
      plan.contains("simulate_s") ? ", each simulated " + plan["simulate_s"].dump() + " s" : "";
  const std::string controller = plan.value("loop", std::string()) == "open"
                                     ? "none: open loop, the passive machine"
                                     : plan["controller"].get<std::string>();
  std::printf(
      "plan %s: %ld evaluations (%s design, n = %ld, %zu dimensions, seed %llu, "
      "controller %s%s)\nwrote %s\n",
      plan["plan_id"].get<std::string>().substr(0, 12).c_str(), plan["evaluations"].get<long>(),
      plan["design"].get<std::string>().c_str(), plan["n"].get<long>(), plan["columns"].size(),
      static_cast<unsigned long long>(plan["seed"].get<std::uint64_t>()), controller.c_str(),
      simulated.c_str(), path.c_str());
}

void run_shard_command(const RunArgs& a) {
  keep_freed_memory();  // thousands of machines built and dropped (process_heap.hpp)
  keep_reductions_beside(a.plan);
  const nlohmann::json plan = read_plan(a.plan);
  require_plan_inputs_unchanged(plan, a.plan);
  const Shard shard = parse_shard(a.shard);
  const long evaluations = plan.at("evaluations").get<long>();
  common::require_writable(a.output);
  // One writer per shard file, from before it is read to the end of the run.
  const auto lock = lock_shard(a.output);
  // Refuse a file of another plan before the evaluator is built (seconds for a large machine).
  std::string repaired;
  completed_indices(a.output, plan.at("plan_id").get<std::string>(), shard, evaluations, &repaired);
  if (!repaired.empty()) std::fprintf(stderr, "note: %s\n", repaired.c_str());
  const PlanSamples samples(plan);
  const auto start = std::chrono::steady_clock::now();
  auto last = start - std::chrono::hours(1);
  long before = -1;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const ShardRunResult r = run_shard(
      a.output, plan.at("plan_id").get<std::string>(), shard, evaluations,
      [&](long index) { return samples.line(index); },
      [&](long index, const std::string& status) { return samples.failed_line(index, status); },
      [&](long done, long total) {
        if (before < 0) before = done;
        const auto now = std::chrono::steady_clock::now();
        if (a.quiet || (done < total && now - last < std::chrono::milliseconds(tty ? 250 : 10000)))
          return;
        last = now;
        const double s = std::chrono::duration<double>(now - start).count();
        std::fprintf(stderr, "%s%s%s", tty ? "\r\033[K" : "",
                     progress_text(done, total, s, before).c_str(),
                     tty && done < total ? "" : "\n");
      });
  if (!a.quiet)
    std::printf("shard %s: %ld samples there already, %ld computed%s\nwrote %s\n", a.shard.c_str(),
                r.already, r.computed,
                r.crashed > 0 ? (", " + std::to_string(r.crashed) +
                                 " written as crashed (two runs died computing it)")
                                    .c_str()
                              : "",
                a.output.c_str());
}

std::vector<std::string> submit(const SubmitArgs& a, const nlohmann::json& plan) {
  const std::string work_dir =
      a.work_dir.empty() ? (fs::path(a.plan).parent_path() / "shards").string() : a.work_dir;
  if (a.engine == "slurm") {
    // The default shard count comes from the plan, not from the cores of the submitting machine.
    SlurmOptions o;
    o.partition = a.partition;
    o.account = a.account;
    o.shards = a.shards;
    o.evaluations = plan.at("evaluations").get<long>();
    o.array_throttle = a.array_throttle;
    o.flexloop_program = this_program();
    o.work_dir = fs::absolute(work_dir).string();
    o.time_limit_min = a.time_limit_min;
    o.sbatch_args = a.sbatch_args;
    return submit_slurm(fs::absolute(a.plan).string(), o);
  }
  const int shards = a.shards > 0 ? a.shards : a.jobs;
  return run_local({this_program(), fs::absolute(a.plan).string(),
                    plan.at("evaluations").get<long>(), shards, a.jobs, work_dir, a.quiet});
}

// The shards streamed once: each line parsed, its numbers taken into the report's columns and the
// worst machines' heaps, and dropped (issue 54: a 10^6-sample report in a few hundred MB).
void report(const std::string& plan_path, const std::vector<std::string>& shards,
            const std::string& out_dir, int worst) {
  keep_reductions_beside(plan_path);  // the worst machines' scenes read the model again
  const nlohmann::json plan = read_plan(plan_path);
  SampleTableBuilder table(plan);
  WorstSamples worst_samples(plan.value("nominal", nlohmann::json()),
                             static_cast<std::size_t>(std::max(worst, 0)));
  std::map<std::string, long> by_status;
  const ShardLines lines =
      merge_shards(plan, shards, [&](long index, const nlohmann::json& sample) {
        table.add(sample);
        worst_samples.add(index, sample);
        const std::string status = sample.value("status", std::string("?"));
        ++by_status[status.substr(0, status.find(':'))];
      });
  const fs::path dir(out_dir);
  common::require_writable(dir / "samples.jsonl");
  lines.write_in_index_order(dir / "samples.jsonl");
  write_campaign_report(plan, table.finish(), out_dir);
  std::printf("campaign %s: %ld samples:", plan["plan_id"].get<std::string>().substr(0, 12).c_str(),
              plan.at("evaluations").get<long>());
  for (const auto& [status, count] : by_status) std::printf(" %ld %s", count, status.c_str());
  std::printf("\nwrote %s/samples.jsonl and the report\n", out_dir.c_str());
  if (worst <= 0) return;
  require_plan_inputs_unchanged(plan, plan_path);
  const MachineDocuments docs(plan.at("scene").get<std::string>());
  std::vector<nlohmann::json> worst_lines;
  for (long index : worst_samples.worst())
    worst_lines.push_back(nlohmann::json::parse(lines.line(index)));
  for (const auto& f : write_sample_scenes(docs, plan, worst_lines, out_dir))
    std::printf("worst: %s\n", f.c_str());
}

void campaign_all(CampaignArgs& a) {
  a.request.scene = a.scene;
  fs::create_directories(a.out_dir);
  const std::string plan_path = (fs::path(a.out_dir) / "plan.json").string();
  keep_reductions_beside(plan_path);
  const nlohmann::json plan = make_plan(a.request);
  write_plan(plan, plan_path);
  SubmitArgs s;
  s.plan = plan_path;
  s.jobs = a.jobs;
  s.shards = a.jobs;
  s.quiet = a.quiet;
  report(plan_path, submit(s, plan), a.out_dir, a.worst);
}

// --method subset: P(unstable) by subset simulation (offline/campaign/subset_campaign.hpp), one
// process, no shards; -n is the samples per level.
void campaign_subset(CampaignArgs& a, bool design_given) {
  keep_freed_memory();
  if (design_given)
    throw common::InputError("--design", "subset simulation draws its own points: no design");
  if (a.request.n < 10 || a.request.n % 10 != 0)
    throw common::InputError("-n",
                             "subset simulation needs a multiple of 10 samples per level "
                             "(p0 = 0.1: n / 10 chains of 10), not " +
                                 std::to_string(a.request.n));
  a.request.scene = a.scene;
  fs::create_directories(a.out_dir);
  const nlohmann::json plan = make_plan(a.request);
  SubsetCampaignOptions o;
  o.settings.per_level = a.request.n;
  o.settings.seed = a.request.seed;
  o.margin = failure_margin_from_name(a.margin);
  o.samples_path = (fs::path(a.out_dir) / "samples.jsonl").string();
  if (!a.quiet)
    o.level_done = [](int level, const SubsetLevel& l) {
      std::fprintf(stderr, "level %d: threshold %.6g, P(g >= b) = %.4g, %ld evaluations%s\n", level,
                   l.threshold, l.fraction, l.evaluations,
                   level == 0 ? "" : (", acceptance " + std::to_string(l.acceptance)).c_str());
    };
  const auto start = std::chrono::steady_clock::now();
  const SubsetCampaign c = run_subset_campaign(plan, o);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const nlohmann::json summary = subset_summary(plan, o, c);
  common::write_text_atomically(fs::path(a.out_dir) / "summary.json", summary.dump(1) + "\n");
  common::write_text_atomically(fs::path(a.out_dir) / "report.md", subset_report_markdown(summary));
  const SubsetResult& r = c.result;
  if (r.estimate > 0)
    std::printf("P(unstable) = %.4g, CoV %.3g, approximate 95 %% interval [%.4g, %.4g]", r.estimate,
                r.cov, r.lo, r.hi);
  else
    std::printf(
        "P(unstable) = 0: no failure within %zu levels; at most about %.4g (the last "
        "level's probability)",
        r.levels.size() - 1, r.hi);
  std::printf(
      " (subset simulation: %ld evaluations in %zu levels, %.1f s)\nwrote %s/summary.json, "
      "report.md, samples.jsonl\n",
      r.evaluations, r.levels.size(), seconds, a.out_dir.c_str());
}

// `required`: false on `campaign` itself, whose subcommands take their own arguments (its
// callback asks for them when it runs the whole campaign).
void add_plan_options(CLI::App* cmd, PlanRequest& r, bool required) {
  cmd->add_option("--uncertain,-u", r.uncertain, "Uncertain parameters file (U.toml)")
      ->required(required)
      ->check(CLI::ExistingFile);
  cmd->add_option("-n", r.n, "Base samples (Saltelli: n (d + 2) evaluations)")->required(required);
  cmd->add_option("--design", r.design, "random, lhs (Latin hypercube), sobol, saltelli")
      ->check(CLI::IsMember({"random", "lhs", "sobol", "saltelli"}))
      ->capture_default_str();
  cmd->add_option("--seed", r.seed, "Seed of the design")->capture_default_str();
  cmd->add_option("--controller", r.controller,
                  "frozen (the nominal design for every machine) or redesigned (the PI designed "
                  "per machine); default: the U.toml's [campaign] controller, else frozen")
      ->check(CLI::IsMember({"frozen", "redesigned"}));
  cmd->add_option("--fmin", r.f_min_hz, "Lowest frequency of the sigma grid, Hz")
      ->check(finite_positive())
      ->capture_default_str();
  cmd->add_option("--fmax", r.f_max_hz, "Highest frequency of the sigma grid, Hz")
      ->check(finite_positive())
      ->capture_default_str();
  cmd->add_option("--points", r.grid_points,
                  "Log-spaced points of the sigma grid (and the "
                  "nominal resonances)")
      ->check(CLI::Range(2, 100000))
      ->capture_default_str();
  cmd->add_option("--simulate", r.simulate_s,
                  "Also run each stable sample's loop for S s with `flexloop sim`'s code: "
                  "saturation, ADC rounding, delays, noise (the nonlinear effects); the sample's "
                  "`sim` figures and the report's simulated / Lyapunov RMS (default: off)")
      ->check(finite_positive());
}

void register_plan(CLI::App* campaign) {
  auto a = std::make_shared<PlanArgs>();
  auto* cmd = campaign->add_subcommand(
      "plan",
      "Write a campaign's plan.json: the scene, the planned parameters, the design, "
      "seed and n, the nominal machine's figures");
  cmd->add_option("scene", a->request.scene, "Scene file (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  add_plan_options(cmd, a->request, true);
  cmd->add_option("-o,--output", a->output, "Plan to write")->capture_default_str();
  cmd->footer(
      "Example:\n  flexloop campaign plan tools/scenes/metrology_frame.toml -u "
      "tools/scenes/metrology_frame_uncertain.toml -n 1000 --design lhs -o out/c/plan.json\n"
      "  flexloop campaign plan tools/scenes/metrology_frame.toml -u "
      "tools/scenes/metrology_frame_uncertain.toml -n 200 --simulate 1 -o out/s/plan.json");
  cmd->callback([a] {
    keep_reductions_beside(a->output);
    write_plan(make_plan(a->request), a->output);
  });
}

void register_run(CLI::App* campaign) {
  auto a = std::make_shared<RunArgs>();
  auto* cmd = campaign->add_subcommand(
      "run",
      "Compute one shard of a plan into a JSONL file (the unit of work of every engine); "
      "idempotent: run again, it completes what is missing");
  cmd->add_option("plan", a->plan, "plan.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("--shard", a->shard, "K/M: the evaluations i with i % M == K")
      ->capture_default_str();
  cmd->add_option("-o,--output", a->output, "Shard file (JSONL) to write or complete")->required();
  cmd->add_flag("--quiet,-q", a->quiet, "No progress on stderr");
  cmd->footer(
      "Example:\n  flexloop campaign run out/c/plan.json --shard 3/8 -o out/c/shard-3.jsonl");
  cmd->callback([a] { run_shard_command(*a); });
}

void register_submit(CLI::App* campaign) {
  auto a = std::make_shared<SubmitArgs>();
  auto* cmd = campaign->add_subcommand(
      "submit",
      "Run every shard of a plan on an engine and wait: local (child processes of "
      "this machine) or slurm (an sbatch array, one element per shard)");
  cmd->add_option("plan", a->plan, "plan.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("--engine", a->engine, "local or slurm")
      ->check(CLI::IsMember({"local", "slurm"}))
      ->capture_default_str();
  cmd->add_option("--shards", a->shards,
                  "Shards (default: local: --jobs; slurm: one per " +
                      std::to_string(kEvaluationsPerShard) +
                      " evaluations, at most the cluster's MaxArraySize)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--jobs,-j", a->jobs, "local: shards at once (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--work-dir", a->work_dir,
                  "Where the shard files go (default: shards/ beside the plan)");
  cmd->add_option("--partition", a->partition, "slurm: partition (default: the cluster's)");
  cmd->add_option("--account", a->account, "slurm: account (default: the cluster's)");
  cmd->add_option("--array-throttle", a->array_throttle,
                  "slurm: at most this many array elements at once (0: no limit)")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--time-limit", a->time_limit_min, "slurm: minutes per array element")
      ->check(finite_positive())
      ->capture_default_str();
  cmd->add_option("--sbatch-arg", a->sbatch_args,
                  "slurm: one more sbatch option, written as its own #SBATCH line (repeatable; "
                  "give it with '=': --sbatch-arg=--mem=2G)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_flag("--quiet,-q", a->quiet, "No progress on stderr");
  cmd->footer(
      "Example:\n  flexloop campaign submit out/c/plan.json --engine local --shards 8\n"
      "  flexloop campaign submit out/c/plan.json --engine slurm --shards 64 "
      "--partition batch --array-throttle 16\n"
      "  flexloop campaign submit out/c/plan.json --engine slurm --sbatch-arg=--mem=2G "
      "--sbatch-arg=--qos=long --sbatch-arg='-M other'\n"
      "  flexloop campaign report out/c/plan.json out/c/shards/shard-*.jsonl --out-dir out/c");
  cmd->callback([a] {
    const nlohmann::json plan = read_plan(a->plan);
    for (const auto& f : submit(*a, plan)) std::printf("shard: %s\n", f.c_str());
  });
}

void register_report(CLI::App* campaign) {
  auto a = std::make_shared<ReportArgs>();
  auto* cmd = campaign->add_subcommand(
      "report",
      "Merge a plan's shard files into samples.jsonl (refusing lines of another plan, "
      "listing missing samples), write the statistics and pictures, and the worst "
      "samples as scenes");
  cmd->add_option("plan", a->plan, "plan.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("shards", a->shards, "Shard files (JSONL)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out-dir", a->out_dir, "Directory for samples.jsonl, the report, worst/")
      ->required();
  cmd->add_option("--worst", a->worst, "Worst samples written as scenes in DIR/worst (0: none)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->footer(
      "Example:\n  flexloop campaign report out/c/plan.json out/c/shards/shard-*.jsonl "
      "--out-dir out/c --worst 3\n  flexloop analyse out/c/worst/sample-17.toml");
  cmd->callback([a] { report(a->plan, a->shards, a->out_dir, a->worst); });
}

}  // namespace

void register_campaign(CLI::App& app) {
  auto a = std::make_shared<CampaignArgs>();
  auto* cmd = app.add_subcommand(
      "campaign",
      "Every machine that will be built: sample the uncertain parameters of the FE model and "
      "the scene (U.toml), re-linearise and judge each machine's sampled loop, and report the "
      "statistics, on this machine's cores (or through plan / run / submit / report, on Slurm)");
  cmd->add_option("scene", a->scene, "Scene file (TOML)")->check(CLI::ExistingFile);
  add_plan_options(cmd, a->request, false);
  cmd->add_option("--jobs,-j", a->jobs, "Processes at once, one shard each (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--out-dir", a->out_dir,
                  "Directory for plan.json, shards/, samples.jsonl, the report and worst/");
  cmd->add_option("--worst", a->worst, "Worst samples written as scenes in DIR/worst (0: none)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", a->quiet, "No progress on stderr");
  cmd->add_option("--method", a->method,
                  "sampling (the design's machines, P(unstable) with its Clopper-Pearson "
                  "interval) or subset (subset simulation for a small P(unstable): -n per level, "
                  "one process, no shards)")
      ->check(CLI::IsMember({"sampling", "subset"}))
      ->capture_default_str();
  cmd->add_option("--margin", a->margin,
                  "subset: the failure margin the levels follow: radius (the sampled loop's "
                  "poles) or disk (the disk margin)")
      ->check(CLI::IsMember({"radius", "disk"}))
      ->capture_default_str();
  cmd->footer(
      "doc/campaign.md has the U.toml format, the figures and the statistics.\n"
      "Example:\n  flexloop campaign tools/scenes/metrology_frame.toml --uncertain "
      "tools/scenes/metrology_frame_uncertain.toml -n 1000 --design lhs --out-dir out/campaign\n"
      "  flexloop campaign tools/scenes/metrology_frame.toml -u "
      "tools/scenes/metrology_frame_uncertain.toml -n 256 --design saltelli --jobs 2 "
      "--out-dir out/sobol\n"
      "  flexloop campaign tools/scenes/metrology_frame.toml -u "
      "tools/scenes/metrology_frame_uncertain.toml -n 200 --simulate 1 --out-dir out/simulated\n"
      "  flexloop campaign tools/scenes/metrology_frame.toml -u "
      "tools/scenes/metrology_frame_uncertain.toml -n 1000 --method subset --out-dir out/rare");
  register_plan(cmd);
  register_run(cmd);
  register_submit(cmd);
  register_report(cmd);
  register_campaign_worst(cmd);
  cmd->require_subcommand(0, 1);
  // The all-in-one form needs its scene; the parts take their own arguments.
  cmd->callback([a, cmd] {
    if (cmd->get_subcommands().empty()) {
      for (const auto& [given, name] :
           {std::pair{!a->scene.empty(), "scene"},
            std::pair{!a->request.uncertain.empty(), "--uncertain"},
            std::pair{cmd->count("-n") > 0, "-n"}, std::pair{!a->out_dir.empty(), "--out-dir"}})
        if (!given) throw CLI::RequiredError(name);
      if (a->method == "subset")
        campaign_subset(*a, cmd->count("--design") > 0);
      else if (cmd->count("--margin") > 0)
        throw common::InputError("--margin",
                                 "the failure margin steers subset simulation: "
                                 "give it with --method subset");
      else
        campaign_all(*a);
    }
  });
}

}  // namespace flexloop::cli
