// SPDX-License-Identifier: BSD-3-Clause
// The sampled closed loop by simulation (offline/pipeline/closed_loop_by_simulation.hpp), what
// `flexloop analyse` shows for a controller FMU, checked against references it does not use:
// - the transform of an impulse response against the analytic H(z) of a first-order system and
//   plant::lti's Hessenberg evaluation of a two-state one;
// - with flexloop's own controllers (state space, PI force feedback), against the matrices'
//   sampled closed loop plant::lti::close_loop_sampled, on the shipped LQG frame and on a
//   machine that is not shipped (one strut under a leaky PI), and a loop that does not settle
//   (three free masses) said to be one;
// - with the PI as the fixture FMU, against the same run with the built-in PI.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "common/sha256.hpp"
#include "offline/pipeline/closed_loop_by_simulation.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/impulse_response_transform.hpp"
#include "tests/fmu/fmu_fixture.hpp"

namespace fs = std::filesystem;
namespace lti = flexloop::plant::lti;
using flexloop::pipeline::closed_loop_by_simulation;

namespace {

// Largest |a_k - b_k| over every entry and frequency, relative to the largest |b_k|.
double relative_difference(const std::vector<Eigen::MatrixXcd>& a,
                           const std::vector<Eigen::MatrixXcd>& b) {
  REQUIRE(a.size() == b.size());
  double difference = 0, largest = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    REQUIRE(a[k].rows() == b[k].rows());
    REQUIRE(a[k].cols() == b[k].cols());
    difference = std::max(difference, (a[k] - b[k]).cwiseAbs().maxCoeff());
    largest = std::max(largest, b[k].cwiseAbs().maxCoeff());
  }
  return difference / largest;
}

std::vector<double> grid_with_resonances(const flexloop::scene::ScenePlant& p, double f_max) {
  return lti::with_resonances(lti::log_frequency_grid_hz(0.5, f_max, 150),
                              p.natural_frequencies_hz);
}

// By simulation and by the matrices, for a scene with one of flexloop's own controllers.
void check_against_matrices(const std::string& scene_path, double tolerance) {
  const auto p = flexloop::scene::build_scene_plant(flexloop::scene::load_scene(scene_path));
  const auto sampled = flexloop::scene::sample_scene(p);
  const auto a =
      flexloop::scene::build_loop_artefact(p, sampled, flexloop::artefact::PlantForm::kDense);
  const auto f = grid_with_resonances(p, 0.45 * a.rate_hz);
  const auto r = closed_loop_by_simulation(a, f);
  CHECK(r.decayed);
  CHECK_FALSE(r.diverged);
  CHECK(r.controller_failure.empty());
  CHECK(r.truncation_bound < 1e-9);
  // The slowest decay the run saw is the matrices' spectral radius (below 1), or inside it
  // when an undamped integrator (a pole at z = 1) sets the spectral radius.
  if (sampled.closed_loop.spectral_radius < 1 - 1e-9)
    CHECK(r.decay_per_sample == Approx(sampled.closed_loop.spectral_radius).margin(1e-4));
  else
    CHECK(r.decay_per_sample < 1);
  const double d = relative_difference(r.response, lti::frequency_response(sampled.closed_loop, f));
  INFO(scene_path << ": " << r.samples << " samples per channel, relative difference " << d);
  CHECK(d < tolerance);
}

// The artefact `a` with a fixture FMU run as `settings` in its controller's place.
flexloop::artefact::LoopArtefact with_fmu(
    flexloop::artefact::LoopArtefact a, const flexloop::controller::fmu::FmuControllerSettings& s) {
  a.controller = flexloop::artefact::ControllerKind::kFmu;
  a.fmu.file = s.file;
  a.fmu.sha256 = flexloop::common::file_sha256(s.file);
  a.fmu.inputs = s.inputs;
  a.fmu.outputs = s.outputs;
  a.fmu.parameters = s.parameters;
  return a;
}

}  // namespace

TEST_CASE("The transform of an impulse response is the sampled system's frequency response",
          "[fmu][analysis]") {
  const double dt = 1e-3, pole = 0.999;
  const std::vector<double> f{0.0, 0.3, 7.0, 120.0, 499.0};
  // h_k = pole^k, in blocks of unequal length: H(z) = 1 / (1 - pole z^-1).
  lti::ImpulseResponseTransform t(f, dt, 1, 1);
  const long n = 40000;
  long k0 = 0;
  for (long block : {1L, 999L, 4096L, 34904L}) {
    Eigen::MatrixXd h(1, block);
    for (long i = 0; i < block; ++i) h(0, i) = std::pow(pole, static_cast<double>(k0 + i));
    t.add(0, k0, h);
    k0 += block;
  }
  REQUIRE(k0 == n);
  const auto H = t.response();
  for (std::size_t i = 0; i < f.size(); ++i) {
    const std::complex<double> z = std::polar(1.0, 2 * M_PI * f[i] * dt);
    const std::complex<double> exact = 1.0 / (1.0 - pole / z);
    // What the run leaves out: pole^n / (1 - pole) at most (4e-15 of the peak here).
    CHECK(std::abs(H[i](0, 0) - exact) < 1e-11 * std::abs(exact));
  }

  // Two inputs, two outputs: a resonance at 50 Hz (radius 0.995) and a lag, against the
  // Hessenberg evaluation of the same matrices.
  lti::DiscreteStateSpace sys;
  sys.dt = dt;
  const double r = 0.995, theta = 2 * M_PI * 50 * dt;
  sys.sys.A.resize(3, 3);
  sys.sys.A << r * std::cos(theta), -r * std::sin(theta), 0, r * std::sin(theta),
      r * std::cos(theta), 0, 0, 0, 0.9;
  sys.sys.B.resize(3, 2);
  sys.sys.B << 1, 0, 0, 0.5, 0.2, 1;
  sys.sys.C.resize(2, 3);
  sys.sys.C << 1, 0, 1, 0, 2, -1;
  sys.sys.D.resize(2, 2);
  sys.sys.D << 0.1, 0, 0, -0.3;
  sys.sys.states = {"a", "b", "c"};
  sys.sys.inputs = {"w1", "w2"};
  sys.sys.outputs = {"z1", "z2"};
  const std::vector<double> g{1.0, 49.9, 50.0, 50.1, 333.0};
  lti::ImpulseResponseTransform two(g, dt, 2, 2);
  for (Eigen::Index j = 0; j < 2; ++j) {
    Eigen::MatrixXd h(2, 12000);
    Eigen::VectorXd x = sys.sys.B.col(j);
    h.col(0) = sys.sys.D.col(j);
    for (Eigen::Index k = 1; k < h.cols(); ++k, x = sys.sys.A * x) h.col(k) = sys.sys.C * x;
    two.add(j, 0, h);
  }
  CHECK(relative_difference(two.response(), lti::frequency_response(sys, g)) < 1e-12);
}

TEST_CASE("The closed loop by simulation equals the matrices' sampled closed loop",
          "[fmu][analysis]") {
  SECTION("the shipped LQG frame (state space, 6 channels)") {
    check_against_matrices("tools/scenes/metrology_frame_lqg.toml", 1e-9);
  }
  SECTION("a machine that is not shipped: one strut under a leaky PI force feedback, 5 kHz") {
    // tests/fixtures/one_strut_200hz.toml at 5 kHz, its integrator leaking at 2 Hz.
    const flexloop::test::TemporaryDirectory dir;
    std::string text = flexloop::test::read_bytes("tests/fixtures/one_strut_200hz.toml");
    for (const auto& [from, to] :
         {std::pair<std::string, std::string>{
              "\"one_strut_model.toml\"",
              "\"" + fs::absolute("tests/fixtures/one_strut_model.toml").string() + "\""},
          {"rate_hz = 200", "rate_hz = 5000"},
          {"zeta = 0.5", "zeta = 0.5\nleak_hz = 2.0"}}) {
      const auto at = text.find(from);
      REQUIRE(at != std::string::npos);
      text.replace(at, from.size(), to);
    }
    std::ofstream(dir.path / "one_strut.toml") << text;
    check_against_matrices((dir.path / "one_strut.toml").string(), 1e-9);
  }
}

TEST_CASE("A loop whose command ramps after a floor impulse is said not to settle",
          "[fmu][analysis]") {
  // Three free masses (tests/fixtures/three_masses.toml, not shipped) under PI force feedback
  // without leak: the sampled loop's matrices have poles at z = 1 (spectral radius 1 + 4e-8),
  // the command ramps until the actuator's limit. No frequency response can be measured.
  const auto p = flexloop::scene::build_scene_plant(
      flexloop::scene::load_scene("tests/fixtures/three_masses.toml"));
  const auto sampled = flexloop::scene::sample_scene(p);
  REQUIRE(sampled.closed_loop.spectral_radius >= 1);
  const auto a =
      flexloop::scene::build_loop_artefact(p, sampled, flexloop::artefact::PlantForm::kDense);
  flexloop::pipeline::ImpulseSettings settings;
  settings.max_samples = 50000;
  const auto r = closed_loop_by_simulation(a, {1.0, 10.0}, settings);
  CHECK_FALSE(r.decayed);
  CHECK(r.samples == settings.max_samples);
}

TEST_CASE("The closed loop by simulation with the PI as the fixture FMU equals the built-in PI's",
          "[fmu][analysis]") {
  const auto p = flexloop::scene::build_scene_plant(
      flexloop::scene::load_scene("tools/scenes/metrology_frame.toml"));
  const auto a = flexloop::scene::build_loop_artefact(p, flexloop::scene::sample_scene(p),
                                                      flexloop::artefact::PlantForm::kDense);
  const auto f = grid_with_resonances(p, 4000);
  // Settled at 1e-12 of the peak, not the default 1e-13: without leak the six integrators hold
  // the round-off of f + u, and the tail's spread stays at about 8e-14 of the peak (measured on
  // both controllers), so at 1e-13 the block where each run stops depends on the last bits (the
  // FMU's C loops against the PI's Eigen products: 12288 against 16384 samples on a Zen 5 host).
  flexloop::pipeline::ImpulseSettings settings;
  settings.decay_tolerance = 1e-12;
  const auto builtin = closed_loop_by_simulation(a, f, settings);
  REQUIRE(builtin.decayed);

  // The same artefact with the fixture FMU in the PI's place (its gains as parameters).
  const auto fmu = closed_loop_by_simulation(
      with_fmu(a, flexloop::test::pi_fmu_settings(a.pi, flexloop::test::pi_fmu_path())), f,
      settings);
  CHECK(fmu.controller_failure.empty());
  CHECK(fmu.decayed);
  CHECK(fmu.samples == builtin.samples);
  CHECK(relative_difference(fmu.response, builtin.response) < 1e-12);
}

TEST_CASE("The shipped LQG as the state-space fixture FMU, by simulation, is the matrices' loop",
          "[fmu][analysis]") {
  // The FMU removes D22 u_{k-1} from the raw sensors itself; its loop measured by simulation is
  // the sampled closed loop plant::lti::close_loop_sampled forms from the design's matrices.
  const auto p = flexloop::scene::build_scene_plant(
      flexloop::scene::load_scene("tools/scenes/metrology_frame_lqg.toml"));
  const auto sampled = flexloop::scene::sample_scene(p);
  const auto a =
      flexloop::scene::build_loop_artefact(p, sampled, flexloop::artefact::PlantForm::kDense);
  const auto f = grid_with_resonances(p, 4000);
  const auto fmu = closed_loop_by_simulation(
      with_fmu(a, flexloop::test::state_space_fmu_settings(a.state_space,
                                                           flexloop::test::state_space_fmu_path())),
      f);
  CHECK(fmu.controller_failure.empty());
  CHECK(fmu.decayed);
  const double d =
      relative_difference(fmu.response, lti::frequency_response(sampled.closed_loop, f));
  INFO(fmu.samples << " samples per channel, relative difference " << d);
  CHECK(d < 1e-9);
  CHECK(relative_difference(fmu.response, closed_loop_by_simulation(a, f).response) < 1e-12);
}
