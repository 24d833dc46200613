// SPDX-License-Identifier: BSD-3-Clause
// Bad controller FMUs are refused at start-up with an error naming the FMU file and what is wrong
// (issue 33): each made here from the good fixture's parts, in a temporary directory.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "common/input_error.hpp"
#include "controller/fmu/fmu_controller.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/metrology.hpp"

namespace fs = std::filesystem;
using flexloop::common::InputError;
using flexloop::controller::fmu::FmuController;
using flexloop::controller::fmu::FmuDirectory;

namespace {

struct BadFmus {
  flexloop::test::TemporaryDirectory temporary;
  const fs::path& dir = temporary.path;
  // The fixture with `from` replaced by `to` in its modelDescription.xml.
  std::string edited(const std::string& name, const std::string& from, const std::string& to) {
    auto entries = flexloop::test::pi_fmu_entries();
    std::string& xml = entries["modelDescription.xml"];
    const auto at = xml.find(from);
    REQUIRE(at != std::string::npos);
    xml.replace(at, from.size(), to);
    const fs::path f = dir / name;
    flexloop::test::write_zip(f, entries);
    return f.string();
  }
};

// Starts the fixture from `file` as the metrology frame's PI, with `edit` applied to the settings.
template <class Edit>
void start(const std::string& file, Edit edit) {
  auto s = flexloop::test::pi_fmu_settings(flexloop::test::metrology_pi_parameters(), file);
  edit(s);
  (void)FmuController::from_settings(s);
}
void start(const std::string& file) {
  start(file, [](auto&) {});
}

}  // namespace

TEST_CASE("The fixture FMU starts and its private directory goes with it", "[fmu]") {
  fs::path unpacked;
  {
    const FmuDirectory d(flexloop::test::pi_fmu_path());
    unpacked = d.path();
    CHECK(fs::is_regular_file(unpacked / "modelDescription.xml"));
    CHECK((fs::status(unpacked).permissions() & fs::perms::others_all) == fs::perms::none);
  }
  CHECK_FALSE(fs::exists(unpacked));
  CHECK_NOTHROW(start(flexloop::test::pi_fmu_path()));
}

TEST_CASE("A file that is not a zip is refused as not an FMU", "[fmu]") {
  BadFmus bad;
  const auto f = bad.dir / "text.fmu";
  std::ofstream(f) << "not an archive\n";
  CHECK_THROWS_WITH(start(f.string()),
                    Catch::StartsWith(f.string() + ": not an FMU: cannot open it as a zip"));
}

TEST_CASE("A zip without modelDescription.xml is refused", "[fmu]") {
  BadFmus bad;
  auto entries = flexloop::test::pi_fmu_entries();
  entries.erase("modelDescription.xml");
  const auto f = bad.dir / "no_description.fmu";
  flexloop::test::write_zip(f, entries);
  CHECK_THROWS_WITH(start(f.string()),
                    f.string() + ": not an FMU: the archive has no modelDescription.xml");
}

TEST_CASE("An FMI 1.0 or 3.0 description is refused", "[fmu]") {
  BadFmus bad;
  for (const std::string version : {"1.0", "3.0"}) {
    const auto f =
        bad.edited("v" + version + ".fmu", "fmiVersion=\"2.0\"", "fmiVersion=\"" + version + "\"");
    CHECK_THROWS_WITH(start(f), f + ": fmiVersion is \"" + version +
                                    "\": flexloop runs FMI 2.0 Co-Simulation FMUs only");
  }
}

TEST_CASE("A Model Exchange only description is refused", "[fmu]") {
  BadFmus bad;
  const auto f = bad.edited("me.fmu", "<CoSimulation ", "<ModelExchange ");
  CHECK_THROWS_WITH(start(f), f + ": a Model Exchange FMU only: flexloop runs Co-Simulation FMUs");
}

TEST_CASE("A missing or mistyped variable is refused naming it", "[fmu]") {
  const auto f = flexloop::test::pi_fmu_path();
  CHECK_THROWS_WITH(start(f, [](auto& s) { s.inputs[5] = "y7"; }),
                    f + ": no variable 'y7' (its real inputs: y1, y2, y3, y4, y5, y6)");
  CHECK_THROWS_WITH(start(f, [](auto& s) { s.outputs[0] = "y1"; }),
                    f + ": variable 'y1' is a real input, not a real output");
  CHECK_THROWS_WITH(start(f, [](auto& s) { s.parameters.emplace_back("gain", 1.0); }),
                    Catch::StartsWith(f + ": no variable 'gain' (its real parameters: K_P_1_1"));
}

TEST_CASE("A fixed step other than the loop period is refused", "[fmu]") {
  BadFmus bad;
  const auto f = bad.edited("fixed.fmu", "canHandleVariableCommunicationStepSize=\"true\"",
                            "canHandleVariableCommunicationStepSize=\"false\"");
  CHECK_NOTHROW(start(f));  // its stepSize 1e-4 s is the metrology frame's period
  CHECK_THROWS_WITH(start(f, [](auto& s) { s.period = 2e-4; }),
                    f + ": its fixed step is 0.0001 s (no canHandleVariableCommunicationStepSize) "
                        "and the loop's period is 0.0002 s");
}

TEST_CASE("A library that does not load is refused with the loader's reason", "[fmu]") {
  BadFmus bad;
  auto entries = flexloop::test::pi_fmu_entries();
  // Longer than an ELF header, so that the loader reads it and says why it refuses it.
  entries["binaries/linux64/pi_force_feedback.so"] = std::string(256, 'x');
  const auto f = bad.dir / "bad_library.fmu";
  flexloop::test::write_zip(f, entries);
  CHECK_THROWS_WITH(
      start(f.string()),
      Catch::StartsWith(f.string() + ": cannot load binaries/linux64/pi_force_feedback.so: ") &&
          Catch::Contains("invalid ELF header"));
}

TEST_CASE("An fmi2Error at initialisation is refused naming the call", "[fmu]") {
  // K_P = -I makes I + K_P singular: the fixture's fmi2ExitInitializationMode returns fmi2Error.
  const auto f = flexloop::test::pi_fmu_path();
  CHECK_THROWS_WITH(start(f,
                          [](auto& s) {
                            for (auto& [name, value] : s.parameters)
                              if (name.starts_with("K_P_")) value = name[4] == name[6] ? -1.0 : 0.0;
                          }),
                    f + ": fmi2ExitInitializationMode returned fmi2Error");
}

TEST_CASE("The state-space fixture refuses bad parameters at initialisation", "[fmu]") {
  // A 12-state, 6-channel design with D22 = I; D = I makes I - D D22 singular (the loop through
  // the sensors' feedthrough is ill-posed: the built-in controller refuses it too).
  const auto f = flexloop::test::state_space_fmu_path();
  flexloop::artefact::StateSpaceParameters p;
  p.A = 0.5 * Eigen::MatrixXd::Identity(12, 12);
  p.B = Eigen::MatrixXd::Ones(12, 6);
  p.C = Eigen::MatrixXd::Ones(6, 12);
  p.D = 0.5 * Eigen::MatrixXd::Identity(6, 6);
  p.feedthrough = Eigen::MatrixXd::Identity(6, 6);
  p.dt = 1e-4;
  p.u_min = Eigen::VectorXd::Constant(1, -1.0);
  p.u_max = Eigen::VectorXd::Constant(1, 1.0);
  const auto start_with = [&](const flexloop::artefact::StateSpaceParameters& q,
                              const std::string& name = "", double value = 0) {
    auto s = flexloop::test::state_space_fmu_settings(q, f);
    for (auto& [n, v] : s.parameters)
      if (n == name) v = value;
    (void)FmuController::from_settings(s);
  };
  const std::string refused = f + ": fmi2ExitInitializationMode returned fmi2Error";
  CHECK_NOTHROW(start_with(p));
  auto singular = p;
  singular.D.setIdentity();
  CHECK_THROWS_WITH(start_with(singular), refused);
  CHECK_THROWS_WITH(start_with(p, "u_min_3", 2.0), refused);  // u_min > u_max
  CHECK_THROWS_WITH(start_with(p, "A_2_5", std::nan("")), refused);
  CHECK_THROWS_WITH(start_with(p, "anti_windup", 2.0), refused);
  CHECK_THROWS_WITH(start_with(p, "feedthrough_delay", 1.5), refused);
  CHECK_THROWS_WITH(start_with(p, "feedthrough_delay", 33.0), refused);
}
