// SPDX-License-Identifier: BSD-3-Clause
// The worst machine in the box (offline/campaign/worst_machine.hpp) against independent
// references: every machine of a campaign drawn from the same ranges with another seed, a full
// grid over the box's corners and inside, the machine written as a scene and judged again by its
// own evaluation, and a box whose worst loop is unstable.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include <unistd.h>

#include "common/input_error.hpp"
#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/campaign/worst_machine.hpp"
#include "offline/scene/scene.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop;
using namespace flexloop::campaign;

namespace {

constexpr const char* kScene = "tests/fixtures/one_strut_campaign.toml";
constexpr const char* kUncertain = "tests/fixtures/one_strut_uncertain.toml";

WorstRequest request(const std::string& figure) {
  WorstRequest r;
  r.plan.scene = kScene;
  r.plan.uncertain = kUncertain;
  r.plan.n = 32;
  r.plan.seed = 3;
  r.plan.grid_points = 60;
  r.figure = figure;
  r.evaluations = 160;
  return r;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("flexloop_test_worst_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE(
    "worst machine: never better than any machine of a 200-sample campaign of the same ranges, "
    "nor than a 5x5x5 grid of the box, for a margin, a peak and an RMS",
    "[campaign][worst]") {
  for (const char* figure : {"disk_margin_db", "peak_sigma", "rms"}) {
    INFO(figure);
    const WorstRequest r = request(figure);
    const WorstMachine w = find_worst_machine(r);
    REQUIRE(w.figures["status"] == "stable");
    CHECK(w.badness >= w.worst_sampled_badness);
    CHECK(w.evaluations <= r.plan.n + r.evaluations);
    // An independent campaign over the same distributions (another seed, random design).
    PlanRequest other = r.plan;
    other.n = 200;
    other.seed = 99;
    other.design = "random";
    const PlanSamples samples(make_plan(other));
    double worst_other = -INFINITY;
    for (long i = 0; i < other.n; ++i)
      worst_other = std::max(worst_other, badness(samples.line(i), w.figure));
    CHECK(w.badness >= worst_other);
    // The box on a grid, its corners included.
    double worst_grid = -INFINITY;
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b)
        for (int c = 0; c < 5; ++c) {
          std::vector<double> u{a / 4.0, b / 4.0, c / 4.0};
          for (std::size_t k = 0; k < u.size(); ++k)
            u[k] = w.box_low[k] + u[k] * (w.box_high[k] - w.box_low[k]);
          worst_grid = std::max(
              worst_grid, badness(samples.figures_at(values_at(samples.columns(), u)), w.figure));
        }
    CHECK(w.badness >= worst_grid - 1e-9 * std::abs(worst_grid));
  }
}

TEST_CASE(
    "worst machine: worst.toml is the machine: judged again from the written files it gives "
    "worst.json's figure, and worst.json names the parameters, the box and the searches",
    "[campaign][worst]") {
  WorstRequest r = request("disk_margin_db");
  r.plan.controller = "redesigned";  // a scene holds the PI's targets: run as it is, redesigned
  const WorstMachine w = find_worst_machine(r);
  const auto dir = temp_dir("files");
  const std::string scene_file = write_worst_machine(w, dir.string());
  std::ifstream in(dir / "worst.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  CHECK(j["figure"] == "disk_margin_db");
  CHECK(j["direction"] == "smallest");
  CHECK(j["value"].get<double>() == w.figures["disk_margin_db"].get<double>());
  CHECK(j["worst_sampled_value"].get<double>() >= j["value"].get<double>());
  CHECK(j["parameters"].size() == 3);
  CHECK(j["box"].size() == 3);
  CHECK(j["starts"].size() == static_cast<std::size_t>(r.starts));
  // The written scene and model, read back as analyse, sim and hil read them.
  const scene::Scene sc = scene::load_scene(scene_file);
  const plant::model::Model model = plant::model::load_model(sc.model_path);
  const SampleEvaluator again(sc, model, {ControllerMode::kRedesigned, {}});
  CHECK(again.nominal()["disk_margin_db"].get<double>() ==
        Approx(j["value"].get<double>()).epsilon(1e-9));
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "worst machine: a box with unstable loops ends at an unstable one, worse than any margin, and "
    "bad requests are refused",
    "[campaign][worst]") {
  // The one-strut loop placed at 40 Hz and sampled at 200 Hz: about one machine in ten of the
  // box has an unstable sampled loop (4 of 40 in a campaign of it).
  const auto dir = temp_dir("unstable");
  std::string text = read_text(kScene);
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"rate_hz = 2000", "rate_hz = 200"},
        {"omega_d_hz = 10.0", "omega_d_hz = 40.0"},
        {"\"one_strut_model.toml\"",
         "\"" + std::filesystem::absolute("tests/fixtures/one_strut_model.toml").string() +
             "\""}}) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  }
  std::ofstream((dir / "scene.toml").string()) << text;
  WorstRequest r = request("disk_margin_db");
  r.plan.scene = (dir / "scene.toml").string();
  const WorstMachine w = find_worst_machine(r);
  std::filesystem::remove_all(dir);
  CHECK(w.figures["status"] == "unstable");
  CHECK(std::isinf(w.badness));
  const nlohmann::json j = worst_machine_json(w);
  CHECK(j["value"].is_null());
  CHECK(j["worst_sampled_value"] == "-inf");

  CHECK_THROWS_AS(find_worst_machine(request("gain_margin")), common::InputError);
  WorstRequest bad = request("peak_sigma");
  bad.starts = 0;
  CHECK_THROWS_AS(find_worst_machine(bad), common::InputError);
}
