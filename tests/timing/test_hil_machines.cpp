// SPDX-License-Identifier: BSD-3-Clause
// Machines that are not the metrology frame, end to end through `flexloop hil` (online/hil):
// built into their loop artefacts, run as plant and controller processes over LCM in a private
// loopback-only namespace, on the general runtime path (channel counts 2/2/2/2, 6/8/8/8 and
// 3/2/2/2; 8, 24 and 106 states). Correctness only, no timing bound: every period ran, the
// messages carried the loop's channel counts (no drop of any kind), the PI answered and the run
// equals hil's replay of its own misses, a loop with no controller ran its plant alone; and a run
// recorded with --lcm-log holds every sample it sent, after the channel map. The flexible arm's
// plant step at 10 kHz is reported (WARN). Needs root for the namespace; without it each case says
// so and checks nothing.
#include <catch2/catch.hpp>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "offline/scene/loop_input.hpp"
#include "online/hil/baseline_json.hpp"
#include "online/hil/hil_run.hpp"
#include "online/loop/channel_map.hpp"
#include "rt/roudi_process.hpp"
#include "tests/timing/private_network.hpp"

using namespace flexloop;
using test::in_private_network;

namespace {

hil::HilOptions options(const std::string& scene, double duration_s) {
  hil::HilOptions o;
  o.loop.loop_path = scene;
  o.loop.duration_s = duration_s;
  o.loop.realtime = {.cpu = 0, .fifo_priority = 80};
  o.controller_cpu = 1;
  o.baseline_duration_s = 0.5;
  o.netns = true;
  return o;
}

void check_run(const nlohmann::json& r, const artefact::LoopArtefact& a, double duration_s) {
  const double cycles = r["cycles"].get<double>();
  const double periods = r["periods"].get<double>();
  const double skipped = r["skipped_periods"].get<double>();
  WARN(a.name << " at " << a.rate_hz << " Hz: " << a.plant.states.size() << " states, cycles "
              << cycles << ", misses " << r["deadline_misses"] << ", plant compute p50/p99 "
              << r["plant_compute_ns"]["p50"] << "/" << r["plant_compute_ns"]["p99"]
              << " ns, controller compute p50 " << r["controller_compute_ns"]["p50"] << " ns");
  CHECK(periods >= std::round(duration_s * a.rate_hz));
  // Baselines of fewer samples than hil::kMinBaselineSamples are flagged, not taken at face value.
  const auto& base = r["baseline"];
  CHECK(base["pingpong"]["too_short"] ==
        (base["pingpong"]["sent"].get<long>() < hil::kMinBaselineSamples));
  CHECK(base["timer"]["too_short"] ==
        (base["timer"]["cycles"].get<long>() < hil::kMinBaselineSamples));
  CHECK(cycles + skipped == periods);
  // Malformed or miscounted messages never occur; stale and reordered answers can (a stalled
  // vCPU delays an answer past its period), and the timing tests judge how often.
  for (const char* reason : {"decode_failure", "channel_count", "non_finite"})
    CHECK(r["dropped_messages"][reason] == 0);
  if (a.controller == artefact::ControllerKind::kNone) {
    CHECK(r["controller"]["kind"] == "none");
    // Nobody answers: the plant holds, then applies the zero command from safe_after on.
    CHECK(r["deadline_misses"].get<double>() == cycles);
    CHECK(r["safe_command_cycles"].get<double>() == cycles - r["safe_after"].get<double>() + 1);
  } else {
    CHECK(r["controller"]["kind"] == "pi_force_feedback");
    for (const char* reason : {"decode_failure", "channel_count", "non_finite"})
      CHECK(r["controller"]["dropped_messages"][reason] == 0);
    // In time for most periods (a shared VM stalls now and then; the timing tests judge that).
    CHECK(r["controller"]["answered"].get<double>() >= 0.9 * cycles);
    CHECK(r["deadline_misses"].get<double>() <= 0.1 * cycles);
    // The run is the loop it timed: hil's replay of its own misses (online/hil/run_replay.hpp)
    // gives each performance output's RMS to rounding, whatever the misses cost.
    const auto& replay = r["physical"]["replay"];
    REQUIRE(replay.contains("performance_rms"));
    CHECK(replay["deadline_misses"] == r["deadline_misses"]);
    CHECK(replay["safe_command_cycles"] == r["safe_command_cycles"]);
    const auto& performance = r["physical"]["performance"];
    REQUIRE(performance.size() == replay["performance_rms"].size());
    for (std::size_t i = 0; i < performance.size(); ++i)
      CHECK(std::abs(performance[i]["rms"].get<double>() /
                         replay["performance_rms"][i].get<double>() -
                     1) <= 1e-9);
  }
}

// Nothing of a run's RouDi or its clients on this host: no iox-roudi process (by its name in
// /proc), no lock holder, socket, lock file or segment, no runtime file of a plant, controller,
// ping or pong in /tmp.
void check_nothing_of_iceoryx_left() {
  for (const auto& e : std::filesystem::directory_iterator("/proc")) {
    std::ifstream comm(e.path() / "comm");
    std::string name;
    if (comm >> name) CHECK(name != "iox-roudi");
  }
  CHECK_FALSE(rt::running_roudi_pid().has_value());
  for (const char* path : {rt::kRoudiSocket, rt::kRoudiSocketLock, rt::kRoudiLockFile,
                           "/dev/shm/iceoryx_mgmt", "/dev/shm/root"})
    CHECK_FALSE(std::filesystem::exists(path));
  // A runtime's files are <name>_<pid> and <name>_<pid>.lock (rt/iceoryx_transport.hpp).
  const std::regex runtime_file("(plant|controller|flexloop_ping|flexloop_pong)_[0-9]+(\\.lock)?");
  for (const auto& e : std::filesystem::directory_iterator("/tmp"))
    CHECK_FALSE(std::regex_match(e.path().filename().string(), runtime_file));
}

}  // namespace

TEST_CASE("hil machines: any channel counts run as plant and controller processes over LCM",
          "[hil][general]") {
  for (const char* scene : {"tools/scenes/two_mass_chain.toml", "tools/scenes/payload_bipods.toml",
                            "tools/scenes/flexible_arm.toml"}) {
    CAPTURE(scene);
    const hil::HilOptions o = options(scene, 2);
    if (!in_private_network(o)) return;
    const auto a = scene::load_loop(scene);
    check_run(hil::run_hil(o, a), a, 2);
  }
}

TEST_CASE(
    "hil machines: over iceoryx a loop is the loop it timed, answers without allocating, and "
    "leaves no RouDi, segment or socket behind",
    "[hil][iceoryx]") {
  // The same checks as over LCM, on the general path (two-mass chain) and a compiled one (the
  // metrology frame), with the run's own RouDi: its ping-pong on iceoryx, the LCM one beside it,
  // the shared-memory floor under both.
  for (const char* scene :
       {"tools/scenes/two_mass_chain.toml", "tools/scenes/metrology_frame.toml"}) {
    CAPTURE(scene);
    hil::HilOptions o = options(scene, 1);
    o.loop.transport = rt::TransportKind::kIceoryx;
    if (!in_private_network(o)) return;
    const auto a = scene::load_loop(scene);
    const nlohmann::json r = hil::run_hil(o, a);
    check_run(r, a, 1);
    CHECK(r["transport"] == "iceoryx");
    const auto& base = r["baseline"];
    CHECK(base["pingpong"]["transport"] == "iceoryx");
    CHECK(base["pingpong"]["answered"].get<double>() > 0);
    CHECK(base["pingpong_lcm"]["transport"] == "lcm");
    CHECK(base["pingpong_lcm"]["answered"].get<double>() > 0);
    CHECK(base["shm_floor"]["round_trips"] == 100'000);
    CHECK(r["controller"]["answered"].get<double>() > 0);
    check_nothing_of_iceoryx_left();
  }
}

TEST_CASE("hil machines: a run recorded with --lcm-log holds every sample and its channel map",
          "[hil][general]") {
  // The plant records what it sends and receives (rt/event_log_recorder.hpp): every sample it
  // published and every answer it received are in the log, after the channel map, at 10 kHz.
  hil::HilOptions o = options("tools/scenes/metrology_frame.toml", 1);
  if (!in_private_network(o)) return;
  const auto log = std::filesystem::temp_directory_path() / "flexloop_test_channel_map.lcmlog";
  std::filesystem::remove(log);
  o.lcm_log = log.string();
  const auto a = scene::load_loop(o.loop.loop_path);
  const nlohmann::json r = hil::run_hil(o, a);
  long sensor_events = 0, command_events = 0, events = 0, first_map = -1;
  nlohmann::json map;
  {
    lcm::LogFile file(log.string(), "r");
    REQUIRE(file.good());
    for (const lcm::LogEvent* e = file.readNextEvent(); e != nullptr; e = file.readNextEvent()) {
      if (e->channel == loop::kChannelMapChannel) {
        const auto* text = static_cast<const char*>(e->data);
        map = nlohmann::json::parse(text, text + e->datalen);
        if (first_map < 0) first_map = events;
      }
      sensor_events += e->channel == "FLEXLOOP_SENSOR";
      command_events += e->channel == "FLEXLOOP_COMMAND";
      ++events;
    }
  }
  std::filesystem::remove(log);
  long answers = 0;
  for (const auto& segment : r["segments"]) answers += segment["answers"].get<long>();
  WARN("log: " << events << " messages, " << sensor_events << " samples of " << r["cycles"]
               << " cycles, " << command_events << " commands for " << answers << " answers");
  CHECK(first_map == 0);
  CHECK(r["lcm_log"]["dropped"] == 0);
  CHECK(r["lcm_log"]["messages"] == events);
  CHECK(sensor_events == r["cycles"].get<long>());
  CHECK(command_events >= answers);  // late and stale answers are received (and logged) too
  CHECK(command_events <= sensor_events);
  REQUIRE(map.is_object());
  CHECK(map["format"] == "flexloop channel map");
  CHECK(map["loop"] == "metrology_frame");
  CHECK(map["channels"]["sensors"].size() == 6);
  CHECK(map["channels"]["actuators"].size() == 6);
  CHECK(map["channels"]["sensors"][0]["name"] == a.channels.sensors[0].name);
  CHECK(map["channels"]["sensors"][0]["unit"] == a.channels.sensors[0].unit);
}
