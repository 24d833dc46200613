// SPDX-License-Identifier: BSD-3-Clause
// A scene's [plant] reduction (offline/scene/scene_plant.hpp reduced_plant): the loop artefact,
// sim and every loop command run the reduced plant. On the three-mass fixture (not shipped; its
// struts stand on two floor plates, so the plant carries the floor's position and velocity as
// states, which the loop starts where the floor is):
//   - modal truncation keeps those four states with their labels as the exact coordinates of its
//     block at the origin: at the full order the plant in modal coordinates gives the full
//     one's outputs to 1e-8, and the reduced loops run bounded from the floor's start;
//   - bad settings name the scene file and the line of the key.
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "common/input_error.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene.hpp"
#include "online/sim/scene_runs.hpp"
#include "tests/support/rest_start.hpp"

using namespace flexloop;

namespace {

// The three-mass fixture's scene with `plant_lines` added to its [plant] table, as a file.
std::string scene_with(const std::string& plant_lines, const std::string& name) {
  std::ifstream in("tests/fixtures/three_masses.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string model = std::filesystem::absolute("tests/fixtures/three_masses_model.toml");
  s = std::regex_replace(s, std::regex("model = \"three_masses_model.toml\""),
                         "model = \"" + model + "\"");
  s = std::regex_replace(s, std::regex("\\[plant\\]\n"), "[plant]\n" + plant_lines);
  const auto dir = std::filesystem::temp_directory_path() / "flexloop_scene_reduction";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << s;
  return path;
}

sim::BothRuns run(const artefact::LoopArtefact& a, double seconds) {
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(seconds / s.dt);
  return sim::run_artefact(a, s, test::from_rest());
}

}  // namespace

TEST_CASE(
    "scene reduction: modal truncation keeps the floor's states and sim runs the reduced loop") {
  const auto full = scene::load_loop(scene_with("", "full.toml"));
  // Order 10 of 10: nothing discarded, only modal coordinates with the floor's states kept.
  const auto same =
      scene::load_loop(scene_with("reduction = \"modal\"\norder = 10\n", "same.toml"));
  const auto reduced =
      scene::load_loop(scene_with("reduction = \"modal-dc\"\norder = 8\n", "reduced.toml"));
  REQUIRE(full.plant.A.rows() == 10);
  REQUIRE(same.plant.A.rows() == 10);
  REQUIRE(reduced.plant.A.rows() == 8);
  for (const char* label : {"pos:x.A", "vel:x.A", "pos:x.B", "vel:x.B"}) {
    INFO(label);
    CHECK(std::count(same.plant.states.begin(), same.plant.states.end(), label) == 1);
    CHECK(std::count(reduced.plant.states.begin(), reduced.plant.states.end(), label) == 1);
  }
  // The same discrete plant in other coordinates: from rest, the same input, the same output.
  {
    std::mt19937 rng(7);
    std::normal_distribution<double> n01;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(10), z = x;
    double worst = 0, scale = 0;
    for (int k = 0; k < 20000; ++k) {
      Eigen::VectorXd u(full.plant.B.cols());
      for (Eigen::Index i = 0; i < u.size(); ++i) u(i) = n01(rng);
      const Eigen::VectorXd y = full.plant.C * x + full.plant.D * u;
      const Eigen::VectorXd ym = same.plant.C * z + same.plant.D * u;
      worst = std::max(worst, (y - ym).cwiseAbs().maxCoeff());
      scale = std::max(scale, y.cwiseAbs().maxCoeff());
      x = full.plant.A * x + full.plant.B * u;
      z = same.plant.A * z + same.plant.B * u;
    }
    INFO("largest output difference " << worst << " of " << scale);
    CHECK(worst <= 1e-8 * scale);
  }
  // In sim both start with the floor's states where the floor is; the modal coordinates start
  // the structure resting on it (the origin block moves it along), the physical ones at zero: a
  // different, decaying transient, so the runs are compared for boundedness only.
  const auto f = run(full, 5), m = run(same, 5), r = run(reduced, 5);
  REQUIRE_FALSE(m.on.divergence.happened());
  REQUIRE_FALSE(r.on.divergence.happened());
  REQUIRE_FALSE(r.off.divergence.happened());
  for (Eigen::Index i = 0; i < f.on.rms_performance.size(); ++i) {
    INFO("output " << i << ": full " << f.on.rms_performance(i) << ", modal coordinates "
                   << m.on.rms_performance(i) << ", 8 states " << r.on.rms_performance(i));
    CHECK(m.on.rms_performance(i) < 10 * f.on.rms_performance(i));
    // The discarded mode carries much of the floor's acceleration (the frame's RMS moves by up
    // to 5x: what `flexloop tradeoff` shows), but the reduced loop runs, bounded, from the
    // floor's start.
    CHECK(std::isfinite(r.on.rms_performance(i)));
    CHECK(r.on.rms_performance(i) < 10 * f.on.rms_performance(i));
  }
}

TEST_CASE("scene reduction: below_hz keeps the modes below it, the rest as static compliance") {
  // The fixture's modes: 32.9, 87.2 and 91.0 Hz, and the floor's four states at the origin.
  const auto full = scene::load_loop(scene_with("", "below_full.toml"));
  const auto first =
      scene::load_loop(scene_with("reduction = \"modal-dc\"\nbelow_hz = 50\n", "below_first.toml"));
  const auto all =
      scene::load_loop(scene_with("reduction = \"modal-dc\"\nbelow_hz = 1000\n", "below_all.toml"));
  CHECK(first.plant.A.rows() == 4 + 2);
  CHECK(all.plant.A.rows() == 10);
  // The kept mode is the 32.9 Hz one: the discrete poles' frequencies, floor's aside.
  const Eigen::VectorXcd poles = first.plant.A.eigenvalues();
  int at_first_mode = 0;
  for (const auto& z : poles) {
    const double hz = std::abs(std::log(z).imag()) / (2 * M_PI * first.dt());
    at_first_mode += std::abs(hz - 32.92) < 0.1 ? 1 : 0;
  }
  CHECK(at_first_mode == 2);
  // Static correction: at 0.5 Hz, far below the discarded 87 and 91 Hz modes, the path from the
  // actuators to the sensors is the full plant's to their dynamic part, (0.5 / 87)^2 ~ 3e-5, in
  // magnitude (in phase the sampled modes lag by half a sample where a feedthrough does not).
  const auto response = [](const artefact::LoopArtefact& a) {
    const Eigen::Index nc = a.actuators(), ns = a.sensors(), n = a.plant.A.rows();
    const std::complex<double> z = std::exp(std::complex<double>(0, 2 * M_PI * 0.5 * a.dt()));
    const Eigen::MatrixXcd zIA = z * Eigen::MatrixXcd::Identity(n, n) - a.plant.A;
    return Eigen::MatrixXcd(
        a.plant.C.bottomRows(ns) *
            zIA.partialPivLu().solve(a.plant.B.rightCols(nc).cast<std::complex<double>>()) +
        a.plant.D.bottomRightCorner(ns, nc));
  };
  const Eigen::MatrixXcd g_full = response(full), g_first = response(first);
  INFO("actuators -> sensors at 0.5 Hz, full\n" << g_full << "\nreduced\n" << g_first);
  CHECK((g_full.cwiseAbs() - g_first.cwiseAbs()).norm() <= 1e-4 * g_full.norm());
}

TEST_CASE("scene reduction: bad settings name the file and line") {
  const auto message = [](const std::string& lines, const std::string& name) -> std::string {
    try {
      scene::load_loop(scene_with(lines, name));
    } catch (const common::InputError& e) {
      return e.what();
    }
    return "no error";
  };
  CHECK_THAT(message("reduction = \"pod\"\norder = 4\n", "a.toml"),
             Catch::Contains("a.toml:8") && Catch::Contains("'pod' is not one of"));
  CHECK_THAT(message("reduction = \"modal\"\n", "b.toml"),
             Catch::Contains("needs either an 'order'") && Catch::Contains("'below_hz'"));
  CHECK_THAT(message("reduction = \"modal\"\norder = 4\nbelow_hz = 50\n", "f.toml"),
             Catch::Contains("f.toml:10") && Catch::Contains("either an 'order'"));
  CHECK_THAT(message("reduction = \"balanced\"\nbelow_hz = 50\n", "g.toml"),
             Catch::Contains("g.toml:9") && Catch::Contains("balanced needs an 'order'"));
  CHECK_THAT(message("reduction = \"modal\"\nbelow_hz = 0\n", "h.toml"),
             Catch::Contains("h.toml:9") && Catch::Contains("must be > 0"));
  CHECK_THAT(message("below_hz = 50\n", "i.toml"), Catch::Contains("belong to a 'reduction'"));
  CHECK_THAT(message("order = 4\n", "c.toml"), Catch::Contains("belong to a 'reduction'"));
  CHECK_THAT(message("reduction = \"modal\"\norder = 11\n", "d.toml"),
             Catch::Contains("d.toml:8") && Catch::Contains("above the plant's 10 states"));
  CHECK_THAT(message("reduction = \"balanced\"\norder = 8\n", "e.toml"),
             Catch::Contains("e.toml:8") && Catch::Contains("floor's position") &&
                 Catch::Contains("modal"));
}
