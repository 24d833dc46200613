// SPDX-License-Identifier: BSD-3-Clause
// Scenes with the user's own controller ([controller] type = "state_space", a controller file):
// - the PI's own law written as a continuous controller file (channels in another order) runs the
//   PI's loop: sim equals the offline sampled closed loop and the PI scene's run;
// - a controller with fewer sensors than actuators (which the PI cannot be) runs as the offline
//   sampled closed loop (plant/lti/feedback_interconnection) says;
// - the shipped LQG design for the metrology frame isolates in sim, every effect on;
// - controller files that do not fit the scene are refused, naming the file and the key.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "artefact/loop_artefact.hpp"
#include "controller/design/pi_force_feedback.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene.hpp"
#include "offline/scene/scene_plant.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tests/support/rest_start.hpp"
#include "tests/support/sampled_loop_reference.hpp"

using namespace flexloop;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

struct TempDir {
  fs::path path =
      fs::temp_directory_path() / ("flexloop_state_space_scenes_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

// The system with its inputs and outputs in reverse order (a file need not follow the scene's).
plant::lti::StateSpace reversed(plant::lti::StateSpace c) {
  c.B = c.B.rowwise().reverse().eval();
  c.D = c.D.colwise().reverse().rowwise().reverse().eval();
  c.C = c.C.colwise().reverse().eval();
  std::reverse(c.inputs.begin(), c.inputs.end());
  std::reverse(c.outputs.begin(), c.outputs.end());
  return c;
}

sim::RunSettings settings(const artefact::LoopArtefact& a, double seconds) {
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(seconds / s.dt);
  return s;
}

}  // namespace

TEST_CASE("state-space scene: the PI's law from a controller file runs the PI's loop",
          "[sim][state_space]") {
  TempDir dir;
  auto pi_scene = scene::load_scene("tests/fixtures/three_masses.toml");
  pi_scene.effects = {};  // the offline closed loop models the bare hardware
  const auto pi_plant = scene::build_scene_plant(pi_scene);
  const fs::path file = dir.path / "pi_as_state_space.json";
  plant::lti::write_continuous(file, reversed(controller::design::pi_state_space(
                                         pi_plant.gains, pi_scene.sensors, pi_scene.actuators)));

  scene::Scene sc = pi_scene;
  sc.controller.type = "state_space";
  sc.controller.file = file.string();
  sc.controller.anti_windup = "none";
  const auto p = scene::build_scene_plant(sc);
  REQUIRE(p.state_space);
  REQUIRE(p.state_space->continuous);
  scene::require_stable_loop(p);
  const auto sampled = scene::sample_scene(p);
  const auto a = scene::build_loop_artefact(p, sampled, artefact::PlantForm::kDense);
  REQUIRE(a.controller == artefact::ControllerKind::kStateSpace);
  // The artefact round-trips through its JSON form.
  const auto back = artefact::loop_artefact_from_json(artefact::to_json(a), "memory");
  CHECK(back.state_space.A == a.state_space.A);
  CHECK(back.state_space.D == a.state_space.D);
  CHECK(back.state_space.feedthrough == a.state_space.feedthrough);
  CHECK(back.state_space.anti_windup == artefact::AntiWindup::kNone);

  const auto s = settings(a, 3.0);
  const auto r = sim::run_artefact(a, s, test::from_rest());
  REQUIRE(r.controlled);
  const auto& cl = sampled.closed_loop.sys;
  const Eigen::VectorXd model = test::reference_rms(a, {cl.A, cl.B, cl.C, cl.D}, 3, s.steps);
  INFO("sim " << r.on.rms_performance.transpose() << ", model " << model.transpose());
  CHECK(test::worst_relative(r.on.rms_performance, model) < 1e-9);

  const auto pi_artefact = scene::build_loop_artefact(pi_plant, scene::sample_scene(pi_plant),
                                                      artefact::PlantForm::kDense);
  const auto pi_run = sim::run_artefact(pi_artefact, s, test::from_rest());
  CHECK(test::worst_relative(r.on.rms_performance, pi_run.on.rms_performance) < 1e-9);
  CHECK(test::worst_relative(r.on.rms_command, pi_run.on.rms_command) < 1e-9);
}

TEST_CASE("state-space scene: fewer sensors than actuators runs as the sampled closed loop",
          "[sim][state_space]") {
  TempDir dir;
  auto sc = scene::load_scene("tests/fixtures/three_masses.toml");
  sc.effects = {};
  const auto pi_plant = scene::build_scene_plant(sc);
  // Integral force feedback on struts a and c (two sensors); strut b is commanded nothing: three
  // actuators, two sensors. Written as a continuous controller, discretised by flexloop.
  const std::vector<std::string> sensors{"stress:e1.a", "stress:e1.c"};
  plant::lti::StateSpace c;
  const double k_i = pi_plant.gains.K_I(0, 0), k_p = pi_plant.gains.K_P(0, 0);
  c.A = -0.5 * Eigen::MatrixXd::Identity(2, 2);  // a leak of 0.5 rad/s
  c.B = Eigen::MatrixXd::Identity(2, 2);
  c.C = Eigen::MatrixXd::Zero(3, 2);
  c.D = Eigen::MatrixXd::Zero(3, 2);
  // Scene actuators: a, c, b.
  c.C(0, 0) = c.C(1, 1) = -k_i;
  c.D(0, 0) = c.D(1, 1) = -k_p;
  c.states = {"xi_a", "xi_c"};
  c.inputs = sensors;
  c.outputs = sc.actuators;
  const fs::path file = dir.path / "two_of_three.json";
  plant::lti::write_continuous(file, c);
  sc.sensors = sensors;
  sc.controller.type = "state_space";
  sc.controller.file = file.string();
  const auto p = scene::build_scene_plant(sc);
  scene::require_stable_loop(p);
  const auto sampled = scene::sample_scene(p);
  const auto a = scene::build_loop_artefact(p, sampled, artefact::PlantForm::kDense);
  REQUIRE(a.sensors() == 2);
  REQUIRE(a.actuators() == 3);
  const auto s = settings(a, 3.0);
  const auto r = sim::run_artefact(a, s, test::from_rest());
  const auto& cl = sampled.closed_loop.sys;
  const Eigen::VectorXd model = test::reference_rms(a, {cl.A, cl.B, cl.C, cl.D}, 3, s.steps);
  INFO("sim " << r.on.rms_performance.transpose() << ", model " << model.transpose());
  CHECK(test::worst_relative(r.on.rms_performance, model) < 1e-9);
  INFO("controller off " << r.off.rms_performance.transpose());
  CHECK(r.on.rms_performance(0) < r.off.rms_performance(0));
}

TEST_CASE("state-space scene: the shipped LQG design isolates the metrology frame",
          "[sim][state_space]") {
  const auto a = scene::load_loop("tools/scenes/metrology_frame_lqg.toml",
                                  {.rate_hz = 0, .form = std::nullopt, .duration_s = 2.0});
  REQUIRE(a.controller == artefact::ControllerKind::kStateSpace);
  REQUIRE(a.state_space.A.rows() == 12);
  const auto pi = scene::load_loop("tools/scenes/metrology_frame.toml",
                                   {.rate_hz = 0, .form = std::nullopt, .duration_s = 2.0});
  const auto s = settings(a, 2.0);
  const auto r = sim::run_artefact(a, s, test::from_rest());
  const auto r_pi = sim::run_artefact(pi, s, test::from_rest());
  // Same floor and hardware seeds: the controller-off runs are one run (the PI scene's on the
  // compiled path, this one on the general path: the order of summation differs).
  CHECK(test::worst_relative(r.off.rms_performance, r_pi.off.rms_performance) < 1e-9);
  for (Eigen::Index i = 0; i < 6; ++i) {
    const double lqg_db = 20 * std::log10(r.on.rms_performance(i) / r.off.rms_performance(i));
    const double pi_db = 20 * std::log10(r_pi.on.rms_performance(i) / r.off.rms_performance(i));
    CAPTURE(i, lqg_db, pi_db);
    CHECK(lqg_db < -30.0);
  }
}

TEST_CASE("state-space scene: a controller file that does not fit is refused, naming it",
          "[sim][state_space]") {
  TempDir dir;
  auto sc = scene::load_scene("tools/scenes/metrology_frame_lqg.toml");
  const auto lqg = plant::lti::read_discrete(sc.controller.file).sys;
  SECTION("a sensor the scene lacks") {
    auto d = lqg;
    d.sys.inputs[2] = "stress:e1.99";
    const fs::path file = dir.path / "wrong_sensor.json";
    plant::lti::write_discrete(file, d);
    sc.controller.file = file.string();
    CHECK_THROWS_WITH(scene::build_scene_plant(sc),
                      Contains(file.string()) && Contains("key 'inputs'") &&
                          Contains("'stress:e1.99' is not one of the scene's sensors"));
  }
  SECTION("designed at another rate") {
    sc.discretisation.rate_hz = 5000;
    CHECK_THROWS_WITH(scene::build_scene_plant(sc), Contains("key 'dt'") &&
                                                        Contains("designed for 10000") &&
                                                        Contains("runs at 5000"));
  }
  // A one-strut scene on the frame's model with the given [controller] lines (line 10 on).
  const auto scene_text = [](const std::string& controller_lines) {
    return "[scene]\nname = \"x\"\nmodel = \"" +
           fs::absolute("tools/models/metrology_frame.toml").string() +
           "\"\n[plant]\ndisturbances = [\"acc:x.9\"]\nactuators = [\"stress:e1.4\"]\n"
           "performance = [\"acc:x.3\"]\nsensors = [\"stress:e1.4\"]\n[controller]\n" +
           controller_lines;
  };
  SECTION("a scene key of the PI beside a state-space controller") {
    const std::string text = scene_text("type = \"state_space\"\nfile = \"" + sc.controller.file +
                                        "\"\nomega_d_hz = 10\n");
    CHECK_THROWS_WITH(scene::parse_scene(text, "inline.toml"),
                      Contains("inline.toml:12") && Contains("unknown key 'omega_d_hz'"));
  }
  SECTION("no file") {
    CHECK_THROWS_WITH(scene::parse_scene(scene_text("type = \"state_space\"\n"), "inline.toml"),
                      Contains("missing key 'file'"));
  }
}
