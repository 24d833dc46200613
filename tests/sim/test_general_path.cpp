// SPDX-License-Identifier: BSD-3-Clause
// `flexloop sim`'s general path (any size, sized at start-up; online/sim/scene_runs_general.cpp):
// - on the metrology frame's default scene (every effect on) it gives the compiled path's
//   figures, dense and modal;
// - on machines with no compiled size (tools/scenes/two_mass_chain.toml: 2 floors, 2 struts;
//   tests/fixtures/three_masses.toml, not shipped: 2 floors, 3 struts) the closed loop equals the
//   offline sampled closed loop (plant/lti/feedback_interconnection) stepped with the same floor
//   sequence, and the controller isolates;
// - machines with unequal channel counts and no controller run as their sampled plant.
// These machines carry the floor's position and velocity as states (their struts stand on the
// floor plates), so they run on their scene's VC floor: the reference draws the same floor from
// the artefact and starts from the same floor state.
#include <catch2/catch.hpp>

#include <cmath>

#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/scene_runs.hpp"
#include "tests/support/rest_start.hpp"
#include "tests/support/sampled_loop_reference.hpp"

using namespace flexloop;

namespace {

sim::BothRuns run(const std::string& scene, artefact::PlantForm form, bool general,
                  double seconds) {
  const auto a = scene::load_loop(scene, {.rate_hz = 0, .form = form, .duration_s = seconds});
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(seconds / s.dt);
  sim::SceneRunOptions o = test::from_rest();
  o.general = general;
  return sim::run_artefact(a, s, o);
}

}  // namespace

TEST_CASE("sim general path: the metrology frame with every effect gives the compiled figures",
          "[sim][general]") {
  const std::string sc = "tools/scenes/metrology_frame.toml";
  const auto compiled = run(sc, artefact::PlantForm::kDense, false, 2.0);
  const auto general = run(sc, artefact::PlantForm::kDense, true, 2.0);
  const auto modal = run(sc, artefact::PlantForm::kModal, true, 2.0);
  // Same hardware, same seeds, the same sample: only the order of summation differs. The ADCs
  // round, so a last-bit difference can flip a code now and then: 1e-9 covers that.
  CHECK(test::worst_relative(general.on.rms_performance, compiled.on.rms_performance) < 1e-9);
  CHECK(test::worst_relative(general.off.rms_performance, compiled.off.rms_performance) < 1e-9);
  CHECK(test::worst_relative(general.on.rms_command, compiled.on.rms_command) < 1e-9);
  CHECK(test::worst_relative(modal.on.rms_performance, compiled.on.rms_performance) < 1e-6);
}

TEST_CASE("sim general path: machines under PI run as their sampled closed loop",
          "[sim][general]") {
  // The shipped two-mass chain (2/2/2/2) and a fixture that is not shipped: three masses on three
  // struts (2 disturbances, 3 actuators, 3 performance outputs, 3 sensors; 5 kHz).
  struct Case {
    const char* scene;
    Eigen::Index states, nz;
  };
  for (const Case c : {Case{"tools/scenes/two_mass_chain.toml", 8, 2},
                       Case{"tests/fixtures/three_masses.toml", 10, 3}}) {
    CAPTURE(c.scene);
    auto sc = scene::load_scene(c.scene);
    sc.effects = {};  // the offline closed loop models the bare hardware
    const auto p = scene::build_scene_plant(sc);
    const auto sampled = scene::sample_scene(p);
    REQUIRE(sampled.plant.sys.nx() == c.states);  // the masses; each floor's position, velocity
    sim::RunSettings s;
    s.dt = sampled.plant.dt;
    s.steps = std::lround(5 / s.dt);  // 5 s
    // Dense only: the floor's double integrators have no modal form (the frame test runs modal).
    const auto a = scene::build_loop_artefact(p, sampled, artefact::PlantForm::kDense);
    const auto r = sim::run_artefact(a, s, test::from_rest());
    // The reference: the offline sampled loop w -> z (plant states first), the same floor.
    const auto& cl = sampled.closed_loop.sys;
    const Eigen::VectorXd rms_model =
        test::reference_rms(a, test::PlantReference{cl.A, cl.B, cl.C, cl.D}, c.nz, s.steps);
    INFO("sim " << r.on.rms_performance.transpose() << ", model " << rms_model.transpose());
    CHECK(test::worst_relative(r.on.rms_performance, rms_model) < 1e-9);
    // Force feedback damps the modes: every mass moves less with it than without.
    for (Eigen::Index i = 0; i < c.nz; ++i)
      CHECK(20 * std::log10(r.on.rms_performance(i) / r.off.rms_performance(i)) < -3.0);
  }
}

TEST_CASE("sim general path: machines without a controller run open loop as their plant",
          "[sim][general]") {
  // The payload on four bipods (6 floors, 8 struts, 8 mount accelerations: unequal counts) and
  // the 100-state flexible arm (3 floors, 2 struts, 2 accelerations), each against its sampled
  // plant w -> z stepped with the same floor draws (the commands stay zero).
  struct Case {
    const char* scene;
    Eigen::Index states, nw, nc, nz;
  };
  for (const Case c : {Case{"tools/scenes/payload_bipods.toml", 24, 6, 8, 8},
                       Case{"tools/scenes/flexible_arm.toml", 106, 3, 2, 2}}) {
    CAPTURE(c.scene);
    auto sc = scene::load_scene(c.scene);
    sc.effects = {};
    const auto p = scene::build_scene_plant(sc);
    const auto sampled = scene::sample_scene(p);
    const auto a = scene::build_loop_artefact(p, sampled, artefact::PlantForm::kDense);
    REQUIRE(a.plant.states.size() == static_cast<std::size_t>(c.states));
    REQUIRE(a.controller == artefact::ControllerKind::kNone);
    REQUIRE(a.disturbances() == c.nw);
    REQUIRE(a.actuators() == c.nc);
    REQUIRE(a.performance() == c.nz);
    sim::RunSettings s;
    s.dt = a.dt();
    s.steps = 5000;
    const auto r = sim::run_artefact(a, s, test::from_rest());
    CHECK_FALSE(r.controlled);
    const auto& d = sampled.plant.sys;
    const Eigen::VectorXd rms_model = test::reference_rms(
        a, test::PlantReference{d.A, d.B.leftCols(c.nw), d.C, d.D.leftCols(c.nw)}, c.nz, s.steps);
    INFO("sim " << r.off.rms_performance.transpose() << ", model " << rms_model.transpose());
    CHECK(rms_model.minCoeff() > 0);
    CHECK(test::worst_relative(r.off.rms_performance, rms_model) < 1e-9);
  }
}
