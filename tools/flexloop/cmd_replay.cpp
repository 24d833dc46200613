// SPDX-License-Identifier: BSD-3-Clause
// `flexloop replay LOOP --plant-report PLANT.json [--controller-record C.json] [--json OUT.json]`:
// a run of `flexloop plant` with a controller process of one's own (doc/external_controller.md),
// replayed in-process sample for sample with the run's own misses (online/hil/run_replay.hpp),
// beside the run's RMS; `flexloop hil` does the same for its own controller process, whose run
// equals its replay to rounding. A controller of one's own that computes the artefact's controller
// in another order of summation comes close, not to rounding, where quantised sensors hide its
// rounding from the loop and the controller's own dynamics grow it until it flips a
// quantisation step (tests/hil/external_c_controller.sh: 1e-4 of the RMS).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "common/json_document.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/hil/run_replay.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

namespace {

struct ReplayArgs {
  std::string loop, plant_report, controller_record, json;
};

// {"ranges": [[first, last], ...], "complete": bool}, ascending and disjoint, seqs >= 1.
loop::SampleRanges read_ranges(const common::JsonReader& parent, const std::string& key) {
  const common::JsonReader r = parent.object(key);
  const nlohmann::json& list = r.get("ranges");
  if (!list.is_array())
    throw common::InputError(
        r.place("ranges"), "expected a list of [first, last], found " + common::json_type_of(list));
  loop::SampleRanges out;
  std::int64_t previous_last = 0;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& e = list[i];
    const std::string place = r.place("ranges") + " entry " + std::to_string(i + 1);
    if (!e.is_array() || e.size() != 2 || !e[0].is_number_integer() || !e[1].is_number_integer())
      throw common::InputError(place, "expected [first, last] (two integers), found " + e.dump());
    const auto first = e[0].get<std::int64_t>(), last = e[1].get<std::int64_t>();
    if (first <= previous_last || last < first)
      throw common::InputError(place,
                               "ranges must ascend, not overlap, and start at seq 1: " + e.dump());
    out.add(first, last);
    previous_last = last;
  }
  if (!r.boolean("complete")) out.mark_incomplete();
  return out;
}

struct PlantRecord {
  double rate_hz = 0;
  hil::RunRecord run;
  loop::LoopOptions options;
  std::vector<std::pair<std::string, double>> performance_rms;  // the run's, by output
};

PlantRecord read_plant_report(const std::string& file) {
  const nlohmann::json j = common::parse_json_file(file);
  const common::JsonReader r(j, file);
  PlantRecord p;
  p.rate_hz = r.number("rate_hz");
  p.run.samples = r.integer("samples", 0, std::numeric_limits<long>::max());
  p.run.unapplied = read_ranges(r, "unapplied_answers");
  p.options.safe_after = static_cast<int>(r.integer("safe_after", 1, 1000000));
  p.options.safe_ramp_s = r.number("safe_ramp_s");
  const std::string start = r.string("start");
  if (start != "stationary" && start != "rest")
    throw common::InputError(r.place("start"), "is \"" + start + "\", expected stationary or rest");
  p.options.start = start == "rest" ? sim::StartKind::kRest : sim::StartKind::kStationary;
  if (r.get("divergence").is_string())
    throw common::InputError(r.place("divergence"), "the run diverged: nothing to replay");
  const common::JsonReader physical = r.object("physical");
  const nlohmann::json& outputs = physical.get("performance");
  if (!outputs.is_array())
    throw common::InputError(physical.place("performance"),
                             "expected a list, found " + common::json_type_of(outputs));
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const common::JsonReader o(outputs[i],
                               physical.place("performance") + " entry " + std::to_string(i + 1));
    p.performance_rms.emplace_back(o.string("name"), o.number("rms"));
  }
  return p;
}

// The loop at the run's rate: a scene is built at it, an artefact must be at it.
artefact::LoopArtefact load_at_rate(const std::string& loop, const std::string& report,
                                    double rate_hz) {
  if (!artefact::is_loop_artefact_file(loop))
    return scene::load_loop(loop, {.rate_hz = rate_hz, .form = std::nullopt, .duration_s = 0});
  artefact::LoopArtefact a = scene::load_loop(loop);
  if (std::abs(a.rate_hz - rate_hz) > 1e-9 * rate_hz)
    throw common::InputError(report + ": key 'rate_hz'",
                             "the run was at " + std::to_string(rate_hz) + " Hz, " + loop +
                                 " is built for " + std::to_string(a.rate_hz) +
                                 " Hz (give the artefact the plant ran)");
  return a;
}

void run(const ReplayArgs& a) {
  if (!a.json.empty()) common::require_writable(a.json);  // before the work, not after it
  PlantRecord p = read_plant_report(a.plant_report);
  if (!a.controller_record.empty()) {
    const nlohmann::json j = common::parse_json_file(a.controller_record);
    p.run.unanswered =
        read_ranges(common::JsonReader(j, a.controller_record), "unanswered_samples");
  }
  const artefact::LoopArtefact loop = load_at_rate(a.loop, a.plant_report, p.rate_hz);
  // The report must be of this loop: its performance outputs, by name and in order.
  const auto& outputs = loop.channels.performance;
  if (p.performance_rms.size() != outputs.size())
    throw common::InputError(a.plant_report + ": key 'physical'",
                             "has " + std::to_string(p.performance_rms.size()) +
                                 " performance outputs, " + a.loop + " has " +
                                 std::to_string(outputs.size()));
  for (std::size_t i = 0; i < outputs.size(); ++i)
    if (p.performance_rms[i].first != outputs[i].name)
      throw common::InputError(a.plant_report + ": key 'physical'",
                               "performance output " + std::to_string(i + 1) + " is '" +
                                   p.performance_rms[i].first + "', " + a.loop + "'s is '" +
                                   outputs[i].name + "': a report of another loop");
  p.options.rate_hz = p.rate_hz;
  const nlohmann::json replay = hil::replay_run(loop, p.options, p.run);
  if (replay.contains("unavailable"))
    throw std::runtime_error("cannot replay " + a.plant_report + ": " +
                             replay["unavailable"].get<std::string>());

  nlohmann::json out = replay;
  out["run_performance_rms"] = nlohmann::json::array();
  std::printf("replay of %s: %lld samples, %lld answers not applied, %lld safe-command cycles\n",
              a.plant_report.c_str(), static_cast<long long>(p.run.samples),
              static_cast<long long>(p.run.unapplied.count()),
              replay["safe_command_cycles"].get<long long>());
  std::printf("RMS of the performance outputs   run            replay         run/replay - 1\n");
  double largest = 0;
  for (std::size_t i = 0; i < p.performance_rms.size(); ++i) {
    const auto& [name, run_rms] = p.performance_rms[i];
    const double replayed = replay["performance_rms"][i].get<double>();
    const double difference = run_rms / replayed - 1;
    largest = std::max(largest, std::abs(difference));
    out["run_performance_rms"].push_back(run_rms);
    std::printf("  %-30s %.6e   %.6e   %+.2e\n", name.c_str(), run_rms, replayed, difference);
  }
  out["largest_relative_difference"] = largest;
  std::printf("largest relative difference %.2e\n", largest);
  if (!a.json.empty()) {
    common::write_json_atomically(a.json, out);
    std::printf("wrote %s\n", a.json.c_str());
  }
}

}  // namespace

void register_replay(CLI::App& app) {
  auto args = std::make_shared<ReplayArgs>();
  auto* cmd = app.add_subcommand(
      "replay",
      "Replay a plant run with its own misses, in-process, beside the run's figures (for a "
      "controller process of your own)");
  cmd->add_option("loop", args->loop, "The scene or loop artefact the plant ran")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--plant-report", args->plant_report,
                  "The plant's report (flexloop plant --json): its rate, samples, unapplied "
                  "answers, safe command and start")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--controller-record", args->controller_record,
                  "JSON with \"unanswered_samples\": {\"ranges\": [[first, last], ...], "
                  "\"complete\": true}, the samples your controller did not answer (default: it "
                  "answered every sample)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--json", args->json, "Write the replay and the run's RMS as JSON to this file");
  cmd->footer(
      "A controller that computes the artefact's controller (doc/controllers.md) gives the run "
      "its replay's RMS, to rounding or (other arithmetic, quantised sensors) close to it; the "
      "replay beside `flexloop sim` is what the misses cost.\n"
      "Example, inside one tools/netns-run -- bash:\n"
      "  flexloop build tools/scenes/metrology_frame_lqg.toml -o /tmp/lqg.json\n"
      "  flexloop-c-controller /tmp/lqg.json --duration 7 &\n"
      "  flexloop plant /tmp/lqg.json --duration 5 --json /tmp/plant.json\n"
      "  flexloop replay /tmp/lqg.json --plant-report /tmp/plant.json\n"
      "Exit: 0 replayed; 2 bad input (file: key says why); 1 a record that cannot be replayed "
      "(why).");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
