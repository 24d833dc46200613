// SPDX-License-Identifier: BSD-3-Clause
// A campaign's sample (offline/campaign/sample_figures.hpp) against independent references: the
// one-mass spring's natural frequency sqrt(k/m)/2pi, `flexloop analyse`'s own analysis.json for
// the nominal machine, a long simulation of each machine's scene (the model written to a file
// and read back, as `flexloop sim` reads it) for the Lyapunov RMS, and a machine beyond buckling.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "offline/campaign/sample_figures.hpp"
#include "offline/pipeline/analyse_scene.hpp"
#include "offline/pipeline/loop_figures.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/scene_plant.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/model/model_parser.hpp"
#include "tests/support/long_run.hpp"

using namespace flexloop;
using campaign::ControllerMode;
using campaign::SampleEvaluator;
using campaign::SampleSettings;

namespace {

constexpr const char* kFrame = "tools/scenes/metrology_frame.toml";
constexpr const char* kFrameModel = "tools/models/metrology_frame.toml";
constexpr double kStrutStiffness = 5263789.013914328;  // N/m, each of the six struts in kFrameModel

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The frame's model text with strut i's stiffness times factors[i] (the struts in file order).
std::string frame_model_text(const std::vector<double>& factors) {
  std::string text = read_text(kFrameModel);
  const std::string key = "stiffness = 5263789.013914328";
  std::size_t at = 0;
  for (const double f : factors) {
    at = text.find(key, at);
    REQUIRE(at != std::string::npos);
    char value[64];
    std::snprintf(value, sizeof value, "stiffness = %.17g", kStrutStiffness * f);
    text.replace(at, key.size(), value);
    at += std::string(value).size();
  }
  return text;
}

// The same change made on the model in memory: every element with the struts' stiffness.
plant::model::Model frame_model(const std::vector<double>& factors) {
  plant::model::Model m = plant::model::load_model(kFrameModel);
  std::size_t i = 0;
  for (auto& el : m.elements)
    for (Eigen::Index k = 0; k < el.stiffness.rows(); ++k)
      if (el.stiffness(k, k) == kStrutStiffness) el.stiffness(k, k) *= factors.at(i++);
  REQUIRE(i == factors.size());
  return m;
}

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("flexloop_test_sample_figures_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

// Runs f with the standard output sent to /dev/null (analyse prints its report there).
template <class F>
void quietly(F f) {
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO), null = ::open("/dev/null", O_WRONLY);
  REQUIRE(saved >= 0);
  REQUIRE(null >= 0);
  ::dup2(null, STDOUT_FILENO);
  ::close(null);
  f();
  std::fflush(stdout);
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
}

}  // namespace

TEST_CASE("sample figures: a one-mass spring's natural frequency is sqrt(k/m)/2pi for each k",
          "[campaign][sample]") {
  const scene::Scene sc = scene::load_scene("tools/scenes/cart.toml");
  const plant::model::Model nominal = plant::model::load_model(sc.model_path);
  const SampleEvaluator evaluator(sc, nominal, {});
  const double m = 2.0;  // kg, node 2 of tools/models/cart_piezo.toml
  for (const double k : {400.0, 800.0, 1300.0}) {
    plant::model::Model machine = nominal;
    for (auto& el : machine.elements)
      if (el.id == "spring") el.stiffness(0, 0) = k;
    const auto j = evaluator.evaluate(sc, machine);
    REQUIRE(j["status"] == "stable");
    REQUIRE(j["natural_frequencies_hz"].size() == 1);
    CHECK(j["natural_frequencies_hz"][0].get<double>() ==
          Approx(std::sqrt(k / m) / numeric::kTwoPi).epsilon(1e-12));
  }
}

TEST_CASE(
    "sample figures: the nominal machine's spectral radius, disk margins, natural frequencies "
    "and closed-loop peak are analyse's numbers",
    "[campaign][sample]") {
  const auto dir = temp_dir("analyse");
  const pipeline::FrequencyGrid grid{0.1, 1000, 120};
  quietly([&] { pipeline::analyse_scene(kFrame, dir.string(), grid); });
  std::ifstream in(dir / "analysis.json");
  const nlohmann::json a = nlohmann::json::parse(in);
  std::filesystem::remove_all(dir);

  const scene::Scene sc = scene::load_scene(kFrame);
  const plant::model::Model model = plant::model::load_model(sc.model_path);
  SampleSettings settings;
  // analyse's grid: the log grid with the passive resonances put in.
  const auto p = scene::build_scene_plant(sc, model);
  settings.sigma_grid_hz = plant::lti::with_resonances(
      plant::lti::log_frequency_grid_hz(grid.f_min_hz, grid.f_max_hz, grid.points),
      p.natural_frequencies_hz);
  const SampleEvaluator evaluator(sc, model, settings);
  const nlohmann::json& n = evaluator.nominal();
  REQUIRE(n["status"] == "stable");
  CHECK(a["closed_loop_stable"] == true);
  CHECK(n["spectral_radius"] == a["sampled_loop"]["spectral_radius"]);
  CHECK(n["natural_frequencies_hz"] == a["natural_frequencies_hz"]);
  const auto& dm = a["disk_margins"];
  CHECK(n["disk_margin_all_deg"] == dm["all_loops"]["phase_deg"]);
  CHECK(n["disk_margin_all_db"].get<double>() ==
        20 * std::log10(dm["all_loops"]["gain_high"].get<double>()));
  double worst_deg = 1e300, worst_high = 1e300;
  for (const auto& [name, loop] : dm["loop_at_a_time"].items()) {
    worst_deg = std::min(worst_deg, loop["phase_deg"].get<double>());
    worst_high = std::min(worst_high, loop["gain_high"].get<double>());
  }
  CHECK(n["disk_margin_deg"].get<double>() == worst_deg);
  CHECK(n["disk_margin_db"].get<double>() == 20 * std::log10(worst_high));
  // sigma_max: analyse plots every singular value (an SVD), a sample needs only the largest
  // (the Hermitian eigenvalues of G^H G, plant/lti/frequency_response.hpp): equal to rounding.
  CHECK(20 * std::log10(n["peak_sigma"].get<double>()) ==
        Approx(a["sigma_max_peak"]["closed_db"].get<double>()).epsilon(1e-12));
  // Evaluating the nominal machine again gives the same bytes.
  CHECK(evaluator.evaluate(sc, model).dump() == n.dump());
}

TEST_CASE(
    "sample figures: for 3 machines the Lyapunov RMS equals 1000 s of the machine's scene run "
    "from its model file within 3 %",
    "[campaign][sample]") {
  // The scene of tests/sim/test_stationary_start.cpp's statistical run: a leak (a stationary
  // closed loop), a white floor, 2 kHz; the sensor noise and the ADC as the frame has them.
  scene::Scene sc = scene::load_scene(kFrame);
  sc.controller.leak_hz = 1.0;
  sc.discretisation.rate_hz = 2000;
  sc.floor = {.spectrum = artefact::FloorSpectrum::kWhite, .rms_mps2 = 1e-3, .seed = 7};
  const SampleEvaluator evaluator(sc, plant::model::load_model(kFrameModel), {});
  const auto dir = temp_dir("sim");
  const std::vector<std::vector<double>> machines{{0.97, 1.02, 1.0, 1.04, 0.99, 0.96},
                                                  {1.05, 1.05, 0.95, 0.95, 1.0, 1.0},
                                                  {0.93, 1.01, 1.03, 0.98, 1.06, 1.02}};
  const auto length =
      flexloop::test::statistical_run(1000, 0.03);  // a tenth, √10 wider, under ASan
  for (std::size_t i = 0; i < machines.size(); ++i) {
    const auto j = evaluator.evaluate(sc, frame_model(machines[i]));
    REQUIRE(j["status"] == "stable");
    CHECK(j["rms"] != evaluator.nominal()["rms"]);
    // The machine's scene on its own model file, built and run as `flexloop sim` does.
    const std::string model_file = (dir / ("machine" + std::to_string(i) + ".toml")).string();
    std::ofstream(model_file) << frame_model_text(machines[i]);
    scene::Scene machine_scene = sc;
    machine_scene.model_path = model_file;
    const auto p = scene::build_scene_plant(machine_scene);
    const auto a =
        scene::build_loop_artefact(p, scene::sample_scene(p), artefact::PlantForm::kDense);
    sim::RunSettings s;
    s.dt = a.dt();
    s.steps = std::lround(length.seconds / s.dt);
    const auto r = sim::run_artefact(a, s, {});
    for (std::size_t c = 0; c < sc.performance.size(); ++c) {
      const double exact = j["rms"][sc.performance[c]].get<double>();
      const double run = r.on.rms_performance(static_cast<Eigen::Index>(c));
      INFO("machine " << i << ", " << sc.performance[c] << ": run " << run << ", exact " << exact);
      CHECK(std::abs(run / exact - 1) <= length.tolerance);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "sample figures: the frozen controller on the nominal machine is the redesigned one, and on "
    "another machine they differ, the redesign placing the machine's own poles",
    "[campaign][sample]") {
  const scene::Scene sc = scene::load_scene(kFrame);
  const auto model = plant::model::load_model(kFrameModel);
  const SampleEvaluator frozen(sc, model, {ControllerMode::kFrozen, {1.0, 10.0, 100.0}});
  const SampleEvaluator redesigned(sc, model, {ControllerMode::kRedesigned, {1.0, 10.0, 100.0}});
  CHECK(frozen.nominal().dump() == redesigned.nominal().dump());
  const auto stiffer = frame_model({1.2, 1.2, 1.2, 1.2, 1.2, 1.2});
  const auto f = frozen.evaluate(sc, stiffer), r = redesigned.evaluate(sc, stiffer);
  REQUIRE(f["status"] == "stable");
  REQUIRE(r["status"] == "stable");
  // The passive machine is the same; the loops are not.
  CHECK(f["natural_frequencies_hz"] == r["natural_frequencies_hz"]);
  CHECK(f["spectral_radius"] != r["spectral_radius"]);
  CHECK(f["rms"] != r["rms"]);
  CHECK(f["rms_open"] == r["rms_open"]);
  // The redesigned gains are the design on the stiffer machine (its own Kdd); the frozen ones
  // the nominal's: the redesigned sample's figures are those of that machine's own scene.
  scene::ScenePlantOptions designed;
  const auto p = scene::build_scene_plant(sc, stiffer, designed);
  const auto p_nominal = scene::build_scene_plant(sc, model);
  CHECK((p.gains.K_I - p_nominal.gains.K_I).norm() > 1e-3 * p_nominal.gains.K_I.norm());
  CHECK(r["spectral_radius"].get<double>() == scene::sampled_loop(p).stability.spectral_radius);
  designed.pi_gains = p_nominal.gains;
  const auto q = scene::build_scene_plant(sc, stiffer, designed);
  CHECK(f["spectral_radius"].get<double>() == scene::sampled_loop(q).stability.spectral_radius);
}

TEST_CASE(
    "sample figures: a machine beyond buckling under its preload is refused, not unstable, and a "
    "controller FMU scene is refused for campaigns",
    "[campaign][sample]") {
  // tests/fixtures/buckled_column.toml: a pinned column under 1.49 times its first buckling load.
  // The nominal machine carries half of it; a machine that carries all of it buckles. The loop:
  // a weak first-order controller of the strut force (a state space, continuous).
  const auto dir = temp_dir("buckling");
  const std::string controller = (dir / "controller.json").string();
  std::ofstream(controller) << R"({"states": ["x"], "inputs": ["stress:e2.b1"],
    "outputs": ["stress:e2.b1"], "A": [[-10.0]], "B": [[1.0]], "C": [[-0.001]], "D": [[0.0]]})";
  scene::Scene sc = scene::load_scene("tests/fixtures/buckled_column.toml");
  sc.controller.type = "state_space";
  sc.controller.file = controller;
  const plant::model::Model loaded = plant::model::load_model(sc.model_path);
  plant::model::Model nominal = loaded;
  for (auto& node : nominal.nodes)
    if (node.force.size() > 0) node.force *= 0.5;
  const SampleEvaluator evaluator(sc, nominal, {});
  CHECK(evaluator.nominal()["natural_frequencies_hz"].is_array());
  const auto j = evaluator.evaluate(sc, loaded);
  std::filesystem::remove_all(dir);
  const std::string status = j["status"];
  INFO(status);
  CHECK(status.rfind("refused: the machine is statically unstable", 0) == 0);
  CHECK(j["spectral_radius"].is_null());
  CHECK(j["rms"].is_null());
  CHECK(j["natural_frequencies_hz"].is_null());
  // The nominal load itself beyond buckling: no campaign.
  CHECK_THROWS_AS(SampleEvaluator(sc, loaded, {}), common::InputError);

  scene::Scene fmu = scene::load_scene(kFrame);
  fmu.controller.type = "fmu";
  fmu.controller.file = "controller.fmu";
  CHECK_THROWS_AS(SampleEvaluator(fmu, plant::model::load_model(kFrameModel), {}),
                  common::InputError);
}

TEST_CASE(
    "sample figures: a scene without a controller is an open-loop campaign of the passive "
    "machine: its figures are the closed-loop scene's passive ones and the plant's own",
    "[campaign][sample]") {
  scene::Scene open = scene::load_scene(kFrame);
  open.controller.type = "none";
  const scene::Scene closed = scene::load_scene(kFrame);
  const auto model = plant::model::load_model(kFrameModel);
  const std::vector<double> grid{1.0, 10.0, 100.0};
  const SampleEvaluator passive(open, model, {ControllerMode::kFrozen, grid});
  const SampleEvaluator loop(closed, model, {ControllerMode::kFrozen, grid});
  CHECK(passive.open_loop());
  CHECK_FALSE(loop.open_loop());
  const auto softer = frame_model({0.8, 0.9, 1.0, 1.1, 1.2, 1.0});
  const auto o = passive.evaluate(open, softer), c = loop.evaluate(closed, softer);
  REQUIRE(o["status"] == "stable");
  // The passive machine is the same machine in both campaigns.
  CHECK(o["natural_frequencies_hz"] == c["natural_frequencies_hz"]);
  CHECK(o["rms_open"] == c["rms_open"]);
  // No loop: no closed-loop RMS and no margins; the radius is the sampled plant's own.
  CHECK(o["rms"].is_null());
  CHECK(o["disk_margin_db"].is_null());
  CHECK(o["disk_margin_all_deg"].is_null());
  const auto p = scene::build_scene_plant(open, softer);
  CHECK(o["spectral_radius"].get<double>() == scene::sample_scene(p).plant.spectral_radius);
  CHECK(o["spectral_radius"].get<double>() < 1);
  // sigma: the passive path floor -> performance on the grid, its largest singular value.
  const auto g = plant::lti::frequency_response(pipeline::floor_to_performance(p), grid);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(g[k]);
    CHECK(o["sigma_max"][k].get<double>() == Approx(svd.singularValues()(0)).epsilon(1e-10));
  }
  // A machine run in an open-loop campaign with --simulate runs the plant alone.
  const auto seeds = campaign::simulation_seeds(1, 0);
  const SampleEvaluator simulated(open, model, {ControllerMode::kFrozen, {}, 0.2});
  const auto s = simulated.evaluate(open, softer, seeds);
  CHECK(s["sim"]["status"] == "ran");
  CHECK(s["sim"]["rms"].is_object());
}
