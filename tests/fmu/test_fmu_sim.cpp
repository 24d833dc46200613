// SPDX-License-Identifier: BSD-3-Clause
// `flexloop sim`'s loop with a controller as a fixture FMU equals the loop with the built-in
// controller to 1e-12 over 10 000 samples (issue 33), both runs from rest with the scene's
// hardware and seeds:
// - the metrology frame's PI (tools/fmu/pi_force_feedback): the scene tests/fixtures/
//   metrology_frame_fmu.toml next to a copy of the FMU, the gains the built-in design computes
//   passed as [controller.parameters];
// - the shipped LQG (tools/scenes/metrology_frame_lqg.toml) and the cart's PI written as a
//   one-state controller file, each as the state-space fixture (tools/fmu/state_space_controller)
//   of its size: the scene with its [controller] replaced by the FMU, the discrete matrices, D22
//   and limits of the built artefact as [controller.parameters].
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/sha256.hpp"
#include "controller/design/pi_force_feedback.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene.hpp"
#include "offline/scene/scene_plant.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/rest_start.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kDuration = 1.0;  // 10 000 samples at 10 kHz

// The fixture scene in `dir` beside a copy of the FMU, its model path absolute and the designed
// gains, leak and limits of `pi` appended as the FMU's parameters.
std::string write_fmu_scene(const fs::path& dir, const flexloop::artefact::PiParameters& pi) {
  fs::copy_file(flexloop::test::pi_fmu_path(), dir / "pi_force_feedback.fmu");
  std::string text = flexloop::test::read_bytes("tests/fixtures/metrology_frame_fmu.toml");
  const std::string model = "\"../../tools/models/metrology_frame.toml\"";
  const auto at = text.find(model);
  REQUIRE(at != std::string::npos);
  text.replace(at, model.size(),
               "\"" + fs::absolute("tools/models/metrology_frame.toml").string() + "\"");
  text += "\n[controller.parameters]\n";
  char line[160];
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      std::snprintf(line, sizeof line, "K_P_%d_%d = %.17g\nK_I_%d_%d = %.17g\n", i + 1, j + 1,
                    pi.K_P(i, j), i + 1, j + 1, pi.K_I(i, j));
      text += line;
    }
  std::snprintf(line, sizeof line, "leak_rad_s = %.17g\nu_min = %.17g\nu_max = %.17g\n",
                pi.leak_rad_s, pi.u_min(0), pi.u_max(0));
  text += line;
  const fs::path scene = dir / "metrology_frame_fmu.toml";
  std::ofstream(scene) << text;
  return scene.string();
}

flexloop::sim::RunResult run_on(const flexloop::artefact::LoopArtefact& a) {
  flexloop::sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(a.duration_s / s.dt);
  s.log_every = 1;
  auto o = flexloop::test::from_rest();
  o.log_on = true;
  o.on_first = true;
  return flexloop::sim::run_artefact(a, s, o).on;
}

// b's log (the FMU's) equals a's (the built-in controller's) to 1e-12 over 10 000 samples, the
// commands being the last `actuators` columns; prints `what` with the largest difference.
void check_same_log(const char* what, const flexloop::sim::RunResult& a,
                    const flexloop::sim::RunResult& b, Eigen::Index actuators) {
  REQUIRE(a.log.rows() == 10000);
  REQUIRE(b.log.rows() == a.log.rows());
  REQUIRE_FALSE(b.divergence.happened());
  const Eigen::MatrixXd diff = b.log.matrix() - a.log.matrix();
  const double largest = diff.cwiseAbs().maxCoeff();
  const double commands = diff.rightCols(actuators).cwiseAbs().maxCoeff();
  const double peak_command = a.log.matrix().rightCols(actuators).cwiseAbs().maxCoeff();
  std::printf(
      "%s, 10000 samples from rest: largest log difference %.3g, commands %.3g N (peak command "
      "%.3g N)\n",
      what, largest, commands, peak_command);
  CAPTURE(what, largest, commands, peak_command);
  CHECK(peak_command > 0);
  CHECK(largest <= 1e-12);
}

// The scene `path` (run from the repository root) written into `dir` as `name` with its model
// path absolute, its [controller] table (to the next table not under it) replaced by
// `controller` and `appended` at its end.
std::string with_controller(const std::string& path, const fs::path& dir, const std::string& name,
                            const std::string& controller, const std::string& appended = "") {
  std::string text = flexloop::test::read_bytes(path);
  const std::string key = "model = \"../models/";
  const auto model = text.find(key);
  REQUIRE(model != std::string::npos);
  text.replace(model, key.size(), "model = \"" + fs::absolute("tools/models").string() + "/");
  const auto from = text.find("\n[controller]\n");
  REQUIRE(from != std::string::npos);
  auto to = from + 1;
  do to = text.find("\n[", to + 1);
  while (to != std::string::npos && text.compare(to, 12, "\n[controller") == 0);
  text.replace(from + 1, to == std::string::npos ? std::string::npos : to - from - 1, controller);
  const fs::path scene = dir / name;
  std::ofstream(scene) << text << appended;
  return scene.string();
}

// The [controller] tables running the state-space fixture `fmu` (copied into `dir`) as `p`, the
// scene's channels mapped to y1.. and u1...
std::string state_space_fmu_controller(const flexloop::artefact::StateSpaceParameters& p,
                                       const std::string& fmu, const fs::path& dir,
                                       const std::vector<std::string>& sensors,
                                       const std::vector<std::string>& actuators) {
  const fs::path copy = dir / fs::path(fmu).filename();
  fs::copy_file(fmu, copy);
  const auto settings = flexloop::test::state_space_fmu_settings(p, copy.string());
  std::string text = "[controller]\ntype = \"fmu\"\nfile = \"" + copy.filename().string() +
                     "\"\n\n[controller.map.sensors]\n";
  for (std::size_t i = 0; i < sensors.size(); ++i)
    text += "\"" + sensors[i] + "\" = \"" + settings.inputs[i] + "\"\n";
  text += "\n[controller.map.actuators]\n";
  for (std::size_t i = 0; i < actuators.size(); ++i)
    text += "\"" + actuators[i] + "\" = \"" + settings.outputs[i] + "\"\n";
  text += "\n[controller.parameters]\n";
  char line[160];
  for (const auto& [name, value] : settings.parameters) {
    std::snprintf(line, sizeof line, "%s = %.17g\n", name.c_str(), value);
    text += line;
  }
  return text + "\n";
}

}  // namespace

TEST_CASE("sim with the PI as the fixture FMU equals sim with the built-in PI to 1e-12", "[fmu]") {
  using flexloop::artefact::ControllerKind;
  const auto builtin = flexloop::scene::load_loop(
      "tools/scenes/metrology_frame.toml", {.rate_hz = 0, .form = {}, .duration_s = kDuration});
  REQUIRE(builtin.controller == ControllerKind::kPiForceFeedback);
  // What the fixture implements: force sensors in series (D22 = I), no extra delay, one limit.
  REQUIRE(builtin.pi.feedthrough.size() == 0);
  REQUIRE(builtin.pi.feedthrough_delay == 0);
  REQUIRE(builtin.pi.u_min.size() == 1);

  const flexloop::test::TemporaryDirectory temporary;
  const fs::path& dir = temporary.path;
  const std::string scene = write_fmu_scene(dir, builtin.pi);
  const auto fmu =
      flexloop::scene::load_loop(scene, {.rate_hz = 0, .form = {}, .duration_s = kDuration});
  REQUIRE(fmu.controller == ControllerKind::kFmu);
  CHECK(fmu.fmu.file == (dir / "pi_force_feedback.fmu").string());
  CHECK(fmu.fmu.sha256 == flexloop::common::file_sha256(flexloop::test::pi_fmu_path()));
  CHECK(fmu.fmu.inputs.front() == "y1");
  CHECK(fmu.fmu.outputs.back() == "u6");
  CHECK(fmu.fmu.parameters.size() == 75);
  CHECK_FALSE(fmu.start.closed_loop.exists());  // an FMU's state is its own: runs start at rest
  // The artefact's JSON carries the FMU as built.
  const auto back = flexloop::artefact::loop_artefact_from_json(to_json(fmu), "test");
  CHECK(back.controller == ControllerKind::kFmu);
  CHECK(back.fmu.sha256 == fmu.fmu.sha256);
  CHECK(back.fmu.inputs == fmu.fmu.inputs);
  CHECK(back.fmu.parameters.size() == fmu.fmu.parameters.size());

  check_same_log("sim metrology frame: FMU PI vs built-in PI", run_on(builtin), run_on(fmu), 6);
}

TEST_CASE("sim with the shipped LQG as the state-space fixture FMU equals sim with it built in",
          "[fmu][state_space]") {
  using flexloop::artefact::ControllerKind;
  const std::string lqg = "tools/scenes/metrology_frame_lqg.toml";
  const auto builtin =
      flexloop::scene::load_loop(lqg, {.rate_hz = 0, .form = {}, .duration_s = kDuration});
  REQUIRE(builtin.controller == ControllerKind::kStateSpace);
  const auto& p = builtin.state_space;
  // The fixture's size; the sensors see their own actuator's command (D22 = I), no extra delay.
  REQUIRE(p.A.rows() == 12);
  REQUIRE(p.B.cols() == 6);
  REQUIRE(p.C.rows() == 6);
  REQUIRE(p.feedthrough.isIdentity(0));
  REQUIRE(p.feedthrough_delay == 0);

  const flexloop::test::TemporaryDirectory temporary;
  const fs::path& dir = temporary.path;
  const auto sc = flexloop::scene::load_scene(lqg);
  const std::string scene =
      with_controller(lqg, dir, "metrology_frame_lqg_fmu.toml",
                      state_space_fmu_controller(p, flexloop::test::state_space_fmu_path(), dir,
                                                 sc.sensors, sc.actuators));
  const auto fmu =
      flexloop::scene::load_loop(scene, {.rate_hz = 0, .form = {}, .duration_s = kDuration});
  REQUIRE(fmu.controller == ControllerKind::kFmu);
  CHECK(fmu.fmu.sha256 == flexloop::common::file_sha256(flexloop::test::state_space_fmu_path()));
  // A, B, C, D, D22, six limits each side, the anti-windup and the feedthrough delay.
  CHECK(fmu.fmu.parameters.size() == 144 + 72 + 72 + 36 + 36 + 6 + 6 + 1 + 1);
  CHECK(fmu.fmu.inputs.front() == "y1");
  CHECK(fmu.fmu.outputs.back() == "u6");

  check_same_log("sim metrology frame LQG: state-space FMU vs built-in", run_on(builtin),
                 run_on(fmu), 6);
}

TEST_CASE("sim with the cart's PI as the one-state fixture FMU equals sim with it built in",
          "[fmu][state_space]") {
  using flexloop::artefact::ControllerKind;
  // The cart's PI (one channel, D22 = 1, D = -K_P: E = 1 / (1 + K_P)) as a continuous controller
  // file; flexloop discretises it at the scene's 1 kHz, so 10 000 samples are 10 s. Unlimited
  // with no anti-windup; limited to 0.03 N (the unlimited run peaks near 0.07 N) with "hold"; a
  // transport delay of 2 samples (the FMU removes D22 u_{k-3}).
  const flexloop::test::TemporaryDirectory temporary;
  const fs::path& dir = temporary.path;
  const std::string cart = "tools/scenes/cart.toml";
  const auto sc = flexloop::scene::load_scene(cart);
  const fs::path file = dir / "cart_pi.json";
  flexloop::plant::lti::write_continuous(
      file, flexloop::controller::design::pi_state_space(
                flexloop::scene::build_scene_plant(sc).gains, sc.sensors, sc.actuators));
  const double seconds = 10.0, limit = 0.03;
  struct Case {
    const char* what;
    const char* controller;  // the [controller] keys beyond type and file
    const char* appended;    // tables appended to the scene
    bool limited;
    int delay;
  };
  for (const Case& c :
       {Case{"sim cart PI as a 1-state controller, unlimited: state-space FMU vs built-in",
             "anti_windup = \"none\"\n", "", false, 0},
        Case{"sim cart PI as a 1-state controller, limit 0.03 N, anti-windup hold: state-space FMU "
             "vs built-in",
             "anti_windup = \"hold\"\nforce_limit_n = 0.03\n", "", true, 0},
        Case{"sim cart PI as a 1-state controller, transport delay 2 samples: state-space FMU vs "
             "built-in",
             "anti_windup = \"none\"\n", "\n[effects.transport_delay]\nsamples = 2\n", false, 2}}) {
    const std::string state_space =
        with_controller(cart, dir, "cart_state_space.toml",
                        "[controller]\ntype = \"state_space\"\nfile = \"" + file.string() + "\"\n" +
                            c.controller + "\n",
                        c.appended);
    const auto builtin =
        flexloop::scene::load_loop(state_space, {.rate_hz = 0, .form = {}, .duration_s = seconds});
    REQUIRE(builtin.controller == ControllerKind::kStateSpace);
    const auto& p = builtin.state_space;
    REQUIRE(p.A.rows() == 1);
    REQUIRE(p.feedthrough.size() == 1);
    REQUIRE(p.feedthrough(0, 0) != 0);
    REQUIRE(p.D(0, 0) != 0);
    REQUIRE(p.u_max.size() == (c.limited ? 1 : 0));
    REQUIRE(p.feedthrough_delay == c.delay);

    fs::remove(dir / "state_space_controller_1x1x1.fmu");
    const std::string scene =
        with_controller(cart, dir, "cart_fmu.toml",
                        state_space_fmu_controller(p, flexloop::test::state_space_1x1x1_fmu_path(),
                                                   dir, sc.sensors, sc.actuators),
                        c.appended);
    const auto fmu =
        flexloop::scene::load_loop(scene, {.rate_hz = 0, .form = {}, .duration_s = seconds});
    REQUIRE(fmu.controller == ControllerKind::kFmu);
    // A, B, C, D, D22, the limits if any, the anti-windup and the feedthrough delay.
    CHECK(fmu.fmu.parameters.size() == (c.limited ? 9u : 7u));

    const auto a = run_on(builtin);
    check_same_log(c.what, a, run_on(fmu), 1);
    if (c.limited) CHECK(a.log.matrix().rightCols(1).cwiseAbs().maxCoeff() == limit);  // binds
  }
}
