// SPDX-License-Identifier: BSD-3-Clause
// The uncertain parameters file (offline/campaign/uncertain_parameters.hpp) and its planning on a
// machine (planned_parameters.hpp): every refusal names the file and line of the entry; unknown
// paths come with the nearest valid names; globs take the elements that have the key;
// unphysical draws are refused at planning unless truncated.
#include <catch2/catch.hpp>

#include <string>

#include "common/input_error.hpp"
#include "offline/campaign/parameter_paths.hpp"
#include "offline/campaign/planned_parameters.hpp"
#include "offline/campaign/uncertain_parameters.hpp"

namespace {

// Using-declarations, not directives: the area's test files share unity batches.
using Catch::Matchers::Contains;
using flexloop::campaign::DistributionKind;
using flexloop::campaign::load_uncertain_parameters;
using flexloop::campaign::MachineDocuments;
using flexloop::campaign::parse_uncertain_parameters;
using flexloop::campaign::plan_columns;
using flexloop::campaign::UncertainParameters;
using flexloop::common::InputError;

const char* kPlanningScene = "tests/fixtures/one_strut_campaign.toml";
const char* kPlanningFrame = "tools/scenes/metrology_frame.toml";

std::string reader_refusal(const std::string& text) {
  try {
    parse_uncertain_parameters(text, "U.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("not refused: " << text);
  return "";
}

std::string planning_refusal(const std::string& text, const char* scene,
                             const std::string& controller = "frozen") {
  const UncertainParameters u = parse_uncertain_parameters(text, "U.toml");
  const MachineDocuments docs(scene);
  try {
    plan_columns(u, docs, controller);
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("not refused at planning: " << text);
  return "";
}

std::string u_entry(const std::string& path, const std::string& rest) {
  return "[[parameter]]\npath = \"" + path + "\"\n" + rest;
}

}  // namespace

TEST_CASE("the fixture U.toml reads as written", "[campaign][uncertain]") {
  const UncertainParameters u =
      load_uncertain_parameters("tests/fixtures/one_strut_uncertain.toml");
  REQUIRE(u.parameters.size() == 3);
  CHECK(u.controller == "frozen");
  CHECK(u.parameters[0].path == "element.strut.stiffness");
  CHECK(u.parameters[0].kind == DistributionKind::kUniform);
  CHECK(*u.parameters[0].low == 3.0e6);
  CHECK(*u.parameters[0].high == 8.0e6);
  CHECK(u.parameters[1].kind == DistributionKind::kNormal);
  CHECK(*u.parameters[1].relative_sd == 0.02);
  CHECK_FALSE(u.parameters[1].mean);
  CHECK(u.parameters[2].kind == DistributionKind::kTruncatedNormal);
  CHECK(u.parameters[0].place == "tests/fixtures/one_strut_uncertain.toml:7");
}

TEST_CASE("bad U.toml entries are refused with file:line", "[campaign][uncertain]") {
  CHECK_THAT(reader_refusal("x = 1\n"), Contains("unknown key 'x'"));
  CHECK_THAT(reader_refusal("[campaign]\ncontroller = \"frozen\"\n"),
             Contains("no [[parameter]] entries"));
  CHECK_THAT(reader_refusal("[campaign]\ncontroller = \"sometimes\"\n" +
                            u_entry("node.mass.mass", "distribution = \"normal\"\nsd = 1\n")),
             Contains("U.toml:2: [campaign]: 'controller' must be"));
  CHECK_THAT(reader_refusal(u_entry("node.mass.mass", "distribution = \"gauss\"\nsd = 1\n")),
             Contains("U.toml:3: [[parameter]]: distribution 'gauss' is not one of"));
  CHECK_THAT(reader_refusal(u_entry("node.mass.mass", "distribution = \"normal\"\n")),
             Contains("give exactly one of 'sd' (absolute) and 'relative_sd'"));
  CHECK_THAT(reader_refusal(u_entry("node.mass.mass",
                                    "distribution = \"normal\"\nsd = 1\nrelative_sd = "
                                    "0.1\n")),
             Contains("U.toml:4: [[parameter]]: give exactly one of"));
  CHECK_THAT(
      reader_refusal(u_entry("node.mass.mass", "distribution = \"uniform\"\nlow = 2\nhigh = 1\n")),
      Contains("U.toml:5: [[parameter]]: 'low' must be below 'high'"));
  CHECK_THAT(reader_refusal(u_entry("node.mass.mass",
                                    "distribution = \"uniform\"\nlow = 1\nhigh = 2\n"
                                    "sd = 3\n")),
             Contains("U.toml:6: [[parameter]]: unknown key 'sd'"));
  CHECK_THAT(reader_refusal(u_entry("node.mass.mass", "distribution = \"normal\"\nsd = -1\n")),
             Contains("'sd' must be positive"));
  CHECK_THAT(reader_refusal(u_entry("node.mass.mass",
                                    "distribution = \"normal\"\nsd = 1\ndraw = "
                                    "\"all\"\n")),
             Contains("U.toml:5: [[parameter]]: 'draw' must be \"each\""));
  CHECK_THAT(
      reader_refusal(u_entry("node.mass.mass", "distribution = \"truncated_normal\"\nsd = 1\n")),
      Contains("a truncated_normal needs 'low' or 'high'"));
  CHECK_THAT(
      reader_refusal(u_entry("node.mass.mass", "distribution = \"lognormal\"\nmedian = 3\n")),
      Contains("missing key 'relative_sd'"));
}

TEST_CASE("an unknown path exits with its line and the nearest valid names",
          "[campaign][uncertain]") {
  const std::string e = planning_refusal(
      u_entry("node.mass.mass", "distribution = \"normal\"\nrelative_sd = 0.01\n") +
          u_entry("element.strut.stifness", "distribution = \"normal\"\nrelative_sd = 0.01\n"),
      kPlanningScene);
  CHECK_THAT(e, Contains("U.toml:5: [[parameter]] 'element.strut.stifness': names no number"));
  CHECK_THAT(e, Contains("nearest valid names: element.strut.stiffness"));
  // A glob that matches nothing says so, with the nearest names too.
  CHECK_THAT(planning_refusal(u_entry("element.*.E", "distribution = \"normal\"\nsd = 1\n"),
                              kPlanningScene),
             Contains("'element.*.E': matches no number of the model or the scene; nearest"));
  // A scene key that is not written in the scene is not a u_entry (the defaults are not).
  CHECK_THAT(planning_refusal(u_entry("controller.leak_hz",
                                      "distribution = \"uniform\"\nlow = "
                                      "0\nhigh = 1\n"),
                              kPlanningScene, "redesigned"),
             Contains("names no number"));
}

TEST_CASE("a glob takes the elements that have the key, one column each or one shared",
          "[campaign][uncertain]") {
  const MachineDocuments docs(kPlanningFrame);
  // The rigid frame beams 1..3 have no stiffness: only the six struts 4..9 match.
  const std::vector<std::string> struts = docs.expand("element.*.stiffness");
  REQUIRE(struts.size() == 6);
  CHECK(struts.front() == "element.4.stiffness");
  CHECK(struts.back() == "element.9.stiffness");
  const auto each = plan_columns(
      parse_uncertain_parameters(
          u_entry("element.*.stiffness", "distribution = \"normal\"\nrelative_sd = 0.05\n"), "U"),
      docs, "frozen");
  CHECK(each.size() == 6);
  const auto shared = plan_columns(parse_uncertain_parameters(u_entry("element.*.stiffness",
                                                                      "distribution = \"normal\"\n"
                                                                      "relative_sd = 0.05\ndraw = "
                                                                      "\"shared\"\n"),
                                                              "U"),
                                   docs, "frozen");
  REQUIRE(shared.size() == 1);
  CHECK(shared[0].name == "element.*.stiffness");
  CHECK(shared[0].paths == struts);
  // Relative to each match's own nominal value.
  CHECK(shared[0].distributions[0].mean == 5263789.013914328);
  CHECK(shared[0].distributions[0].sd == Approx(0.05 * 5263789.013914328).epsilon(1e-15));
  // The reference machine's U.toml plans: 6 + 1 + 6 + 1 + 1 dimensions.
  CHECK(plan_columns(load_uncertain_parameters("tools/scenes/metrology_frame_uncertain.toml"), docs,
                     "frozen")
            .size() == 15);
}

TEST_CASE("an unphysical draw is refused at planning unless truncated", "[campaign][uncertain]") {
  // 20 %: the 1e-9 quantile (-6 sd) is negative.
  CHECK_THAT(planning_refusal(u_entry("element.strut.stiffness",
                                      "distribution = \"normal\"\nrelative_sd = 0.2\n"),
                              kPlanningScene),
             Contains("U.toml:1: [[parameter]] 'element.strut.stiffness': element.strut.stiffness "
                      "can be drawn at"));
  CHECK_THAT(planning_refusal(u_entry("element.strut.stiffness",
                                      "distribution = \"normal\"\nrelative_sd = 0.2\n"),
                              kPlanningScene),
             Contains("use distribution = \"truncated_normal\" with low = 0"));
  CHECK_THAT(planning_refusal(
                 u_entry("node.mass.mass", "distribution = \"uniform\"\nlow = -1\nhigh = 200\n"),
                 kPlanningScene),
             Contains("must not be negative; set 'low' to 0 or above"));
  CHECK_THAT(planning_refusal(u_entry("effects.force_sensor.noise_rms_n",
                                      "distribution = \"normal\"\nsd = 0.002\n"),
                              kPlanningScene),
             Contains("a sensor noise must not be negative"));
  CHECK_THAT(planning_refusal(u_entry("effects.actuator.gain",
                                      "distribution = \"truncated_"
                                      "normal\"\nsd = 1\nlow = -0.5\n"),
                              kPlanningScene),
             Contains("the actuator gain (it keeps its sign) must be positive; set its 'low'"));
  const MachineDocuments docs(kPlanningScene);
  // The same spreads truncated at the physical bound, and 10 % (-6 sd > 0): accepted.
  CHECK(plan_columns(parse_uncertain_parameters(u_entry("element.strut.stiffness",
                                                        "distribution = \"truncated_normal\""
                                                        "\nrelative_sd = 0.2\nlow = 0\n"),
                                                "U"),
                     docs, "frozen")
            .size() == 1);
  CHECK(plan_columns(
            parse_uncertain_parameters(u_entry("element.strut.stiffness",
                                               "distribution = \"normal\"\nrelative_sd = 0.1\n"),
                                       "U"),
            docs, "frozen")
            .size() == 1);
}

TEST_CASE("a number drawn twice and PI keys under a frozen controller are refused",
          "[campaign][uncertain]") {
  CHECK_THAT(planning_refusal(u_entry("element.*.stiffness",
                                      "distribution = \"normal\"\nrelative_"
                                      "sd = 0.01\n") +
                                  u_entry("element.6.stiffness",
                                          "distribution = \"normal\"\nrelative_sd = 0.01\n"),
                              kPlanningFrame),
             Contains("U.toml:5: [[parameter]] 'element.6.stiffness': element.6.stiffness is drawn "
                      "already by the entry at U.toml:1"));
  const std::string zeta = u_entry("controller.zeta",
                                   "distribution = \"uniform\"\nlow = 0.3\n"
                                   "high = 0.7\n");
  CHECK_THAT(planning_refusal(zeta, kPlanningScene, "frozen"),
             Contains("set [campaign] controller = \"redesigned\""));
  CHECK(plan_columns(parse_uncertain_parameters(zeta, "U"), MachineDocuments(kPlanningScene),
                     "redesigned")
            .size() == 1);
}
