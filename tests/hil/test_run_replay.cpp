// SPDX-License-Identifier: BSD-3-Clause
// hil's replay of a run (online/hil/run_replay.hpp): the run's stations on a synthetic clock with
// the misses the run recorded. Checked against the in-process loop of `flexloop sim` (an
// independent loop, not the stations): with no miss the replay is sim's loop bit for bit, on
// machines and controllers other than the reference frame's PI; a miss changes it as the plant's
// hold and safe command say; a record that cannot have happened is refused, not replayed.
#include <catch2/catch.hpp>
#include <string>

#include "offline/scene/loop_input.hpp"
#include "online/hil/run_replay.hpp"
#include "online/sim/scene_runs.hpp"

using namespace flexloop;

namespace {

Eigen::VectorXd rms(const nlohmann::json& replay, const char* key = "performance_rms") {
  REQUIRE(replay.contains(key));
  const auto v = replay[key].get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

constexpr long kSamples = 4000;

}  // namespace

TEST_CASE("hil replay: with no miss the replay is sim's loop, sample for sample", "[replay]") {
  const std::string scene = GENERATE(std::string("tools/scenes/two_mass_chain.toml"),
                                     std::string("tools/scenes/cart.toml"),
                                     std::string("tools/scenes/metrology_frame_lqg.toml"),
                                     std::string("tools/scenes/metrology_frame_all_effects.toml"));
  CAPTURE(scene);
  const artefact::LoopArtefact loop = scene::load_loop(scene);
  const loop::LoopOptions o;  // stationary start, as hil's plant and controller processes
  hil::RunRecord record;
  record.samples = kSamples;
  const nlohmann::json replay = hil::replay_run(loop, o, record);
  sim::RunSettings s;
  s.dt = loop.dt();
  s.steps = kSamples;
  sim::SceneRunOptions general;
  general.general = true;  // the replay's path
  const sim::BothRuns sim = sim::run_artefact(loop, s, general);
  REQUIRE(sim.controlled);
  CHECK(replay["deadline_misses"] == 0);
  CHECK(rms(replay) == sim.on.rms_performance);
  CHECK(rms(replay, "command_rms") == sim.on.rms_command);
}

TEST_CASE("hil replay: recorded misses hold the command, then go safe, as the plant did",
          "[replay]") {
  const artefact::LoopArtefact loop = scene::load_loop("tools/scenes/two_mass_chain.toml");
  loop::LoopOptions o;
  o.safe_after = 5;
  const auto replay = [&](std::initializer_list<std::pair<std::int64_t, std::int64_t>> unapplied,
                          std::initializer_list<std::pair<std::int64_t, std::int64_t>> unanswered) {
    hil::RunRecord r;
    r.samples = kSamples;
    for (const auto& [first, last] : unapplied) r.unapplied.add(first, last);
    for (const auto& [first, last] : unanswered) r.unanswered.add(first, last);
    return hil::replay_run(loop, o, r);
  };
  const nlohmann::json ideal = replay({}, {});
  // Two late answers (the controller answered, the plant held): 2 misses, no safe command.
  const nlohmann::json late = replay({{100, 100}, {2000, 2000}}, {});
  INFO(late.dump());
  CHECK(late["deadline_misses"] == 2);
  CHECK(late["safe_command_cycles"] == 0);
  CHECK(rms(late) != rms(ideal));
  // A stalled controller (samples 500..519 unanswered): 20 misses, the last 16 safe.
  const nlohmann::json stall = replay({{500, 519}}, {{500, 519}});
  CHECK(stall["deadline_misses"] == 20);
  CHECK(stall["safe_command_cycles"] == 20 - o.safe_after + 1);
  CHECK((rms(stall) - rms(ideal)).cwiseAbs().maxCoeff() > 1e-6 * rms(ideal).maxCoeff());
  // A record that cannot have happened: the plant applied an answer nobody sent.
  const nlohmann::json impossible = replay({}, {{700, 700}});
  REQUIRE(impossible.contains("unavailable"));
  CHECK(impossible["unavailable"].get<std::string>().find("sample 700") != std::string::npos);
  // A record the processes could not keep whole.
  hil::RunRecord incomplete;
  incomplete.samples = kSamples;
  incomplete.unanswered.mark_incomplete();
  CHECK(hil::replay_run(loop, o, incomplete).contains("unavailable"));
}
