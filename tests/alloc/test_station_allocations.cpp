// SPDX-License-Identifier: BSD-3-Clause
// No allocation in the controller process's answer (online/loop/controller_station.hpp), also
// where it starts its controller at the loop's stationary start: the first sample of an epoch
// sets the controller's state and remembered commands from the drawn start, and the plant's
// first samples say it holds the start's command (applied_seq 0, applied_scale > 0). The draw is
// made before (start-up); every answer after it, across two plant restarts, allocates nothing.
// Each controller the process runs: the compiled PI (metrology frame), the state-space LQG.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "offline/scene/loop_input.hpp"
#include "online/loop/controller_station.hpp"
#include "online/loop/loop_controller.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/loop_start.hpp"
#include "tests/support/allocation_counter.hpp"

using namespace flexloop;

namespace {

// Samples of three plant epochs, the first two samples of each saying the start's command is
// held; built before counting (their sensor vectors are the messages' own allocations).
std::vector<flexloop_msgs::sensor_sample_t> samples(const artefact::LoopArtefact& a) {
  std::vector<flexloop_msgs::sensor_sample_t> out;
  for (std::int64_t epoch = 1; epoch <= 3; ++epoch)
    for (std::int64_t seq = 1; seq <= 2000; ++seq) {
      flexloop_msgs::sensor_sample_t s{};
      s.plant_epoch = epoch;
      s.seq = seq;
      s.applied_seq = seq <= 2 ? 0 : seq - 1;
      s.applied_scale = 1.0;
      s.n_sensors = static_cast<std::int16_t>(a.sensors());
      for (Eigen::Index i = 0; i < a.sensors(); ++i)
        s.sensors.push_back(1e-3 * std::sin(0.01 * static_cast<double>(seq * (i + 1))));
      out.push_back(s);
    }
  return out;
}

}  // namespace

TEST_CASE("allocation: the controller process's answers from a stationary start allocate nothing",
          "[alloc]") {
  for (const std::string scene :
       {"tools/scenes/metrology_frame.toml", "tools/scenes/metrology_frame_lqg.toml"}) {
    const artefact::LoopArtefact a = scene::load_loop(scene);
    REQUIRE(a.start.closed_loop.exists());
    const sim::DrawnStart drawn =
        sim::draw_start(a, a.start.closed_loop, sim::floor_start_states(a));
    const auto messages = samples(a);
    loop::with_loop_controller(a, [&](auto controller) {
      loop::ControllerStation station(std::move(controller), 5, drawn);
      double sum = 0;
      const std::uint64_t before = test::allocation_count();
      for (const auto& s : messages) sum += station.answer(s).commands[0];
      CHECK(test::allocation_count() - before == 0);
      CHECK(station.resyncs() == 2);
      CHECK(std::isfinite(sum));
    });
  }
}
