// `flexloop sim`'s loop with the metrology frame's PI as the fixture FMU equals the loop with the
// built-in PI to 1e-12 over 10 000 samples (issue 33): the scene tests/fixtures/
// metrology_frame_fmu.toml next to a copy of the FMU, the gains the built-in design computes
// passed as [controller.parameters]; both runs from rest with the scene's hardware and seeds.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "offline/scene/loop_input.hpp"
#include "online/sim/scene_runs.hpp"
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
  CHECK(fmu.fmu.sha256 == flexloop::scene::file_sha256(flexloop::test::pi_fmu_path()));
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

  const auto a = run_on(builtin), b = run_on(fmu);
  REQUIRE(a.log.rows() == 10000);
  REQUIRE(b.log.rows() == a.log.rows());
  REQUIRE_FALSE(b.divergence.happened());
  const Eigen::MatrixXd diff = b.log.matrix() - a.log.matrix();
  const double largest = diff.cwiseAbs().maxCoeff();
  const double commands = diff.rightCols(6).cwiseAbs().maxCoeff();
  const double peak_command = a.log.matrix().rightCols(6).cwiseAbs().maxCoeff();
  std::printf(
      "sim metrology frame, 10000 samples from rest: FMU PI vs built-in PI: largest log "
      "difference %.3g, commands %.3g N (peak command %.3g N)\n",
      largest, commands, peak_command);
  CAPTURE(largest, commands, peak_command);
  CHECK(peak_command > 0);
  CHECK(largest <= 1e-12);
}
