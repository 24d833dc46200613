// SPDX-License-Identifier: BSD-3-Clause
// Drawn values applied to the model and scene documents (offline/campaign/parameter_paths.hpp)
// and read back by the project's readers: the parsed value is the drawn one; a one-mass spring's
// natural frequency is sqrt(k/m)/(2 pi) of each sample's drawn k and m (the project's own
// linearisation and modal analysis); the worst samples written as scenes read back as the
// machines they were.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/input_error.hpp"
#include "offline/campaign/parameter_paths.hpp"
#include "offline/campaign/planned_parameters.hpp"
#include "offline/campaign/uncertain_parameters.hpp"
#include "offline/campaign/worst_samples.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

namespace {

// Using-declarations, not directives: the area's test files share unity batches.
namespace common = flexloop::common;
namespace plant = flexloop::plant;
namespace scene = flexloop::scene;
using flexloop::campaign::columns_from_plan;
using flexloop::campaign::columns_json;
using flexloop::campaign::edit_distance;
using flexloop::campaign::load_uncertain_parameters;
using flexloop::campaign::Machine;
using flexloop::campaign::MachineDocuments;
using flexloop::campaign::nearest_names;
using flexloop::campaign::parameters_json;
using flexloop::campaign::ParameterValues;
using flexloop::campaign::parse_uncertain_parameters;
using flexloop::campaign::plan_columns;
using flexloop::campaign::UncertainParameters;
using flexloop::campaign::values_at;
using flexloop::campaign::worst_samples;
using flexloop::campaign::write_worst_samples;

const char* kPathsScene = "tests/fixtures/one_strut_campaign.toml";

// The test's own unit points: a regular grid shifted per column (the product's come from the
// design, offline/campaign/designs.hpp).
std::vector<double> grid_point(long i, long n, std::size_t d) {
  std::vector<double> u(d);
  for (std::size_t c = 0; c < d; ++c)
    u[c] = std::fmod((static_cast<double>(i) + 0.5) / static_cast<double>(n) + 0.31 * c, 1.0);
  return u;
}

double value_of(const ParameterValues& v, const std::string& path) {
  for (const auto& [p, x] : v)
    if (p == path) return x;
  FAIL("no value for " << path);
  return 0;
}

}  // namespace

TEST_CASE("the paths of a machine are the numbers written in its files", "[campaign][paths]") {
  const MachineDocuments docs(kPathsScene);
  CHECK(docs.paths() == std::vector<std::string>{
                            "element.strut.stiffness", "element.strut.damping", "node.mass.mass",
                            "controller.omega_d_hz", "controller.zeta", "floor.rms_mps2",
                            "effects.actuator.gain", "effects.actuator.force_limit_n",
                            "effects.force_sensor.noise_rms_n",
                            "effects.force_sensor.adc_range_n"});
  CHECK(docs.site("element.strut.stiffness").nominal == 5263789.013914328);
  CHECK(docs.site("node.mass.mass").nominal == 100.0);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(nearest_names("node.mass.mas", docs.paths(), 1) ==
        std::vector<std::string>{"node.mass.mass"});
}

TEST_CASE("a drawn value is the value the project's readers read", "[campaign][paths]") {
  const MachineDocuments docs(kPathsScene);
  const double k = 4.123456789012345e6, m = 97.31234567890123, gain = 0.8765432109876543;
  const Machine machine = docs.apply(
      {{"element.strut.stiffness", k}, {"node.mass.mass", m}, {"effects.actuator.gain", gain}});
  CHECK(machine.model.elements[0].stiffness(0, 0) == k);
  CHECK(machine.model.nodes[1].mass == m);
  CHECK(machine.scene.effects.actuator.gain == gain);
  // Nothing else moved: damping, the other scene numbers, the model the scene names.
  CHECK(machine.model.elements[0].damping(0, 0) == 167.5516081914556);
  CHECK(machine.scene.controller.omega_d_hz == 10.0);
  CHECK(machine.scene.model_path == docs.nominal_machine().scene.model_path);
  // A 3-D inertia entry (the metrology frame's lens, Izz) by its index in the array.
  const MachineDocuments frame("tools/scenes/metrology_frame.toml");
  const Machine lens = frame.apply({{"node.1.inertia[2]", 130.5}});
  CHECK(lens.model.nodes[0].inertia(2, 2) == 130.5);
  CHECK(lens.model.nodes[0].inertia(0, 0) == frame.nominal_machine().model.nodes[0].inertia(0, 0));
  // A value the reader refuses throws its InputError (the sample is then "refused: ...").
  CHECK_THROWS_AS(docs.apply({{"element.strut.stiffness", -1.0}}), common::InputError);
}

TEST_CASE("each sample's natural frequency of a one-mass spring is sqrt(k/m)/(2 pi)",
          "[campaign][paths]") {
  const MachineDocuments docs(kPathsScene);
  const auto columns = plan_columns(
      load_uncertain_parameters("tests/fixtures/one_strut_uncertain.toml"), docs, "frozen");
  REQUIRE(columns.size() == 3);
  constexpr long kSamples = 7;
  for (long i = 0; i < kSamples; ++i) {
    const ParameterValues values = values_at(columns, grid_point(i, kSamples, columns.size()));
    const double k = value_of(values, "element.strut.stiffness");
    const double m = value_of(values, "node.mass.mass");
    CHECK(k >= 3.0e6);
    CHECK(k < 8.0e6);
    const Machine machine = docs.apply(values);
    const auto lin =
        plant::model::linearise(machine.model, plant::model::model_operating_point(machine.model));
    // The dynamic block (the strut's extension; the floor's y is prescribed).
    const int nd = machine.model.nd();
    const auto modes =
        plant::lti::natural_modes(lin.M.topLeftCorner(nd, nd), lin.K.topLeftCorner(nd, nd));
    REQUIRE(modes.frequencies_hz.size() == 1);
    CHECK(modes.frequencies_hz(0) ==
          Approx(std::sqrt(k / m) / (2 * std::numbers::pi)).epsilon(1e-12));
  }
}

TEST_CASE("the worst samples are written as a scene and its model that read back as drawn",
          "[campaign][worst]") {
  const MachineDocuments docs(kPathsScene);
  const nlohmann::json plan{{"plan_id", "0123abcd"},
                            {"scene", kPathsScene},
                            {"nominal", {{"rms", {{"acc:y.mass", 1.0}}}}}};
  auto sample = [](long index, const char* status, double radius, double rms, double k) {
    return nlohmann::json{
        {"index", index},
        {"status", status},
        {"spectral_radius", radius},
        {"rms", {{"acc:y.mass", rms}}},
        {"parameters", {{"element.strut.stiffness", k}, {"effects.actuator.gain", 0.9}}}};
  };
  std::vector<nlohmann::json> samples = {
      sample(0, "stable", 0.99, 3.0, 4e6), sample(1, "unstable", 1.02, 1.0, 5e6),
      sample(2, "stable", 0.995, 1.0, 6e6), sample(3, "refused: buckling", 0, 0, 7e6),
      sample(4, "unstable", 1.05, 1.0, 3.5e6)};
  // Any unstable: by spectral radius, unstable first; refused ones are no machine to run.
  CHECK(worst_samples(samples, plan["nominal"], 10) == std::vector<std::size_t>{4, 1, 2, 0});
  // All stable: by the worst RMS against the nominal.
  samples[1]["status"] = samples[4]["status"] = "stable";
  samples[1]["rms"]["acc:y.mass"] = 2.0;
  CHECK(worst_samples(samples, plan["nominal"], 2) == std::vector<std::size_t>{0, 1});

  const auto dir = std::filesystem::temp_directory_path() / "flexloop_test_worst";
  std::filesystem::remove_all(dir);
  const auto files = write_worst_samples(docs, plan, samples, 1, dir.string());
  REQUIRE(files.size() == 1);
  CHECK(files[0] == (dir / "worst" / "sample-0.toml").string());
  const scene::Scene sc = scene::load_scene(files[0]);
  CHECK(sc.name == "one_strut_campaign_sample_0");
  CHECK(sc.model_path == (dir / "worst" / "sample-0_model.toml").string());
  CHECK(sc.effects.actuator.gain == 0.9);
  const plant::model::Model m = plant::model::load_model(sc.model_path);
  CHECK(m.elements[0].stiffness(0, 0) == 4e6);
  CHECK(m.nodes[1].mass == 100.0);
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "a shared draw over a body's inertia scales its entries alike, and the plan's record of "
    "the columns gives the same values",
    "[campaign][paths]") {
  const MachineDocuments frame("tools/scenes/metrology_frame.toml");
  const UncertainParameters u = parse_uncertain_parameters(
      "[[parameter]]\npath = \"node.1.inertia[*]\"\ndistribution = \"normal\"\nrelative_sd = "
      "0.05\ndraw = \"shared\"\n\n[[parameter]]\npath = \"element.*.stiffness\"\ndistribution = "
      "\"uniform\"\nlow = 4e6\nhigh = 6e6\n",
      "U.toml");
  const auto columns = plan_columns(u, frame, "frozen");
  REQUIRE(columns.size() == 7);  // the inertia's one shared column, six struts
  CHECK(columns[0].paths ==
        std::vector<std::string>{"node.1.inertia[0]", "node.1.inertia[1]", "node.1.inertia[2]"});
  const std::vector<double> point = grid_point(3, 10, columns.size());
  const ParameterValues values = values_at(columns, point);
  const Machine m = frame.apply(values);
  const Eigen::Matrix3d nominal = frame.nominal_machine().model.nodes[0].inertia;
  const double factor = m.model.nodes[0].inertia(0, 0) / nominal(0, 0);
  CHECK(factor != 1.0);
  for (int a = 1; a < 3; ++a)
    CHECK(m.model.nodes[0].inertia(a, a) / nominal(a, a) == Approx(factor).epsilon(1e-14));

  const nlohmann::json plan{{"parameters", parameters_json(u, columns)},
                            {"columns", columns_json(columns)}};
  const nlohmann::json reread = nlohmann::json::parse(plan.dump());
  CHECK(values_at(columns_from_plan(reread), point) == values);
}
