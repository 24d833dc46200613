// SPDX-License-Identifier: BSD-3-Clause
// The real-time loop's plant station runs the scene's hardware effects (issue 6 composed into
// issue 7): with every answer in time, the stations on the all-effects scene (gravity preload,
// VC-C floor, lagging saturating piezos, sensors with gain error, noise, quantisation and delay,
// transport delay) reproduce the in-process simulation of `flexloop sim` bit for bit.
#include <catch2/catch.hpp>

#include <algorithm>

#include "online/sim/closed_loop_run.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/loop_start.hpp"
#include "tests/hil/station_fixture.hpp"

using namespace flexloop;
using namespace flexloop::test;

namespace {

constexpr long kSteps = 4000;

// The stations on `hw` against the in-process run `reference` (every sample logged: t, floor (6),
// performance (6), performance sensors (6), sensors (6), commands (6)), every answer in time.
template <class Hardware, class Controller>
void stations_reproduce(loop::PlantStation<Hardware>& station,
                        loop::ControllerStation<Controller>& controller,
                        const sim::RunResult& reference) {
  const Eigen::Index z0 = 1 + 6, u0 = 1 + 6 + 3 * 6;
  ChannelVector sum_u2 = ChannelVector::Zero();
  double z_differ = 0, u_differ = 0;  // largest |stations - in-process| over every sample
  for (long k = 0; k < kSteps; ++k) {
    const std::int64_t due = k * kPeriod;
    station.settle(due);
    const auto& s = station.sample(due);
    REQUIRE_FALSE(deliver(controller.samples(), s, due + kTransit).has_value());
    auto& cmd = controller.answer(*controller.samples().take());
    cmd.t_ns = due + kAnswerAfter;
    const Eigen::Map<const ChannelVector> u(cmd.commands.data());
    sum_u2 += u.cwiseAbs2();
    // Sample k's performance is the plant's output after the command of sample k - 1 acted.
    z_differ = std::max(z_differ, (station.hardware().performance().transpose() -
                                   reference.log.matrix().row(k).segment(z0, 6))
                                      .cwiseAbs()
                                      .maxCoeff());
    u_differ = std::max(
        u_differ,
        (u.transpose() - reference.log.matrix().row(k).segment(u0, 6)).cwiseAbs().maxCoeff());
    REQUIRE_FALSE(deliver(station.commands(), cmd, due + kAnswerAfter + kTransit).has_value());
  }
  const ChannelVector rms_u = (sum_u2 / kSteps).cwiseSqrt();
  INFO("largest difference over " << kSteps << " samples: performance " << z_differ << ", command "
                                  << u_differ);
  CHECK(z_differ == 0);
  CHECK(u_differ == 0);
  CHECK(rms_u.maxCoeff() > 0);  // the controller acted
  CHECK(station.deadline_misses() == 0);
}

const sim::RunSettings kLogged{.steps = kSteps, .dt = 1e-4, .log_every = 1, .chunk_steps = kSteps};

}  // namespace

TEST_CASE(
    "hil stations with every effect of the all-effects scene reproduce the in-process "
    "simulation exactly") {
  const artefact::LoopArtefact scene =
      scene::load_loop("tools/scenes/metrology_frame_all_effects.toml");
  const auto& d = scene.plant;
  REQUIRE(d.A.rows() == 24);  // the gravity preload adds the floor's position and velocity
  REQUIRE(scene.dt() == kLogged.dt);
  const auto plant =
      plant::runtime::DensePlant<double, 24, 12, 12, 6>::from_matrices(d.A, d.B, d.C, d.D);
  sim::with_hardware<6, 6>(scene, plant, [&](auto hw) {
    SECTION("from rest") {
      const sim::RunResult reference = sim::run_closed_loop(hw, hil_controller(scene), kLogged, {});
      loop::PlantStation<decltype(hw)> station(hw,
                                               {.safe_after = 5, .epoch = 3, .period_ns = kPeriod});
      loop::ControllerStation controller(hil_controller(scene), 5);
      stations_reproduce(station, controller, reference);
    }
    SECTION("from the stationary start, drawn apart by the plant and the controller side") {
      // The in-process loop, as sim starts it.
      auto started = hw;
      auto controller = hil_controller(scene);
      REQUIRE(sim::start_loop(scene, scene.start.closed_loop, sim::StartKind::kStationary, started,
                              controller));
      const sim::RunResult reference = sim::run_closed_loop(started, controller, kLogged, {});
      // The plant process: its own hardware and draw; the controller process: the floor's start
      // from the artefact alone (online/loop/controller_loop.cpp).
      auto plant_side = hw;
      const auto drawn =
          sim::draw_start(scene, sim::run_start(scene), sim::floor_filter_states(plant_side));
      sim::start_hardware_at(scene, drawn, plant_side);
      loop::PlantStation<decltype(hw)> station(plant_side,
                                               {.safe_after = 5, .epoch = 3, .period_ns = kPeriod});
      station.start_command(ChannelVector(drawn.last_command));
      loop::ControllerStation controller_side(
          hil_controller(scene), 5,
          sim::draw_start(scene, sim::run_start(scene), sim::floor_start_states(scene)));
      stations_reproduce(station, controller_side, reference);
    }
  });
}
