// SPDX-License-Identifier: BSD-3-Clause
// The floor between samples (issue 35, item 2; doc/performance.md "The floor between samples"):
// the runtime holds the floor's sample-mean acceleration over each sample; the machine's floor
// moves continuously. Both stationary RMS values are exact (Lyapunov equations): the loop as it
// runs (scene::stationary_moments) against the continuous floor and plant sampled exactly
// together (scene::continuous_floor_moments), the actuators held and the controller discrete in
// both.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/loop_start_builder.hpp"
#include "offline/scene/scene_plant.hpp"

using namespace flexloop;

namespace {

// Worst |RMS held / RMS continuous - 1| over the performance outputs.
double worst_rms_error(const scene::ScenePlant& p, const artefact::LoopArtefact& a, bool closed) {
  const auto held = scene::stationary_moments(a, closed).performance_mean_square;
  const auto exact = scene::continuous_floor_moments(p, a, closed).performance_mean_square;
  return (held.cwiseQuotient(exact).cwiseSqrt().array() - 1).abs().maxCoeff();
}

struct Machine {
  scene::ScenePlant plant;
  artefact::LoopArtefact artefact;
};

Machine machine(scene::Scene sc, double rate_hz) {
  sc.discretisation.rate_hz = rate_hz;
  auto p = scene::build_scene_plant(sc);
  auto a = scene::build_loop_artefact(p, scene::sample_scene(p), artefact::PlantForm::kDense);
  return {std::move(p), std::move(a)};
}

}  // namespace

TEST_CASE(
    "floor between samples: the metrology frame's held floor is within 1 % of the continuous "
    "floor in RMS open and closed loop at 10 kHz",
    "[sim][floor]") {
  auto sc = scene::load_scene("tools/scenes/metrology_frame.toml");
  sc.controller.leak_hz = 1.0;  // a stationary closed loop
  const Machine m = machine(sc, 10000);
  const double off = worst_rms_error(m.plant, m.artefact, false);
  const double on = worst_rms_error(m.plant, m.artefact, true);
  WARN("metrology frame, 10 kHz: held vs continuous floor, worst RMS error off " << off << ", on "
                                                                                 << on);
  CHECK(off <= 0.01);
  CHECK(on <= 0.01);
}

// The table of doc/performance.md. Run: build/check/tests/test_sim "[.floor_report]"
TEST_CASE("floor between samples report", "[.floor_report]") {
  struct Case {
    const char* what;
    const char* scene;
    bool preload, leak;
  };
  for (const Case c :
       {Case{"metrology frame", "tools/scenes/metrology_frame.toml", false, true},
        Case{"metrology frame, gravity preload (floor states)", "tools/scenes/metrology_frame.toml",
             true, true},
        Case{"three masses (floor states)", "tests/fixtures/three_masses.toml", false, false},
        Case{"flexible arm (floor states)", "tools/scenes/flexible_arm.toml", false, false}}) {
    for (const double rate : {1000.0, 2000.0, 5000.0, 10000.0}) {
      auto sc = scene::load_scene(c.scene);
      if (c.preload) sc.gravity_preload = true;
      if (c.leak) sc.controller.leak_hz = 1.0;
      try {
        const Machine m = machine(sc, rate);
        const bool controlled = m.artefact.controller != artefact::ControllerKind::kNone;
        for (const bool closed : {false, true}) {
          if (closed && !controlled) continue;
          const auto held = scene::stationary_moments(m.artefact, closed).performance_mean_square;
          const auto exact =
              scene::continuous_floor_moments(m.plant, m.artefact, closed).performance_mean_square;
          const Eigen::ArrayXd ratio = held.cwiseQuotient(exact).cwiseSqrt().array();
          std::printf("| %s | %s | %.0f Hz | %.4f … %.4f |\n", c.what, closed ? "closed" : "open",
                      rate, ratio.minCoeff(), ratio.maxCoeff());
        }
      } catch (const std::exception& e) {
        std::printf("| %s | | %.0f Hz | %s |\n", c.what, rate, e.what());
      }
    }
  }
}
