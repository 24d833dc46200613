// SPDX-License-Identifier: BSD-3-Clause
// A controller FMU's modelDescription.xml read to the FMI 2.0 standard, and its library loaded only
// once it is proven to be inside the archive and of the standard's platform and version (issue 46,
// doc/controllers.md "Refusals: the archive and its description"). Each bad FMU is the PI fixture
// with one thing changed, zipped by the test; each refusal is a flexloop::InputError (exit 2 on
// the command line) naming the FMU file and the variable or attribute, and the private TMPDIR the
// loader unpacks into is empty afterwards.
#include <dlfcn.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "controller/fmu/fmu_archive.hpp"
#include "controller/fmu/fmu_controller.hpp"
#include "controller/fmu/fmu_description.hpp"
#include "controller/fmu/fmu_library.hpp"
#include "tests/fmu/fmu_archive_fixture.hpp"
#include "tests/support/metrology.hpp"

namespace fs = std::filesystem;
using flexloop::controller::fmu::FmuController;
using flexloop::controller::fmu::FmuControllerSettings;
using flexloop::controller::fmu::FmuDescription;
using flexloop::controller::fmu::FmuLibrary;
using flexloop::test::PrivateTmpdir;

namespace {

// The PI fixture with `from` replaced by `to` in its description (and its library replaced by the
// file `library` when one is given), as `name` in the test's inputs.
std::string described_fmu(const PrivateTmpdir& t, const std::string& name, const std::string& from,
                          const std::string& to, const std::string& library = "") {
  auto entries = flexloop::test::pi_fixture_and({});
  for (auto& e : entries) {
    if (e.name == "modelDescription.xml") {
      const auto at = e.bytes.find(from);
      REQUIRE(at != std::string::npos);
      e.bytes.replace(at, from.size(), to);
    }
    if (!library.empty() && e.name.ends_with(".so")) e.bytes = flexloop::test::read_bytes(library);
  }
  const fs::path f = t.inputs / name;
  flexloop::test::write_test_zip(f, entries);
  return f.string();
}

FmuControllerSettings pi_settings(const std::string& fmu) {
  return flexloop::test::pi_fmu_settings(flexloop::test::metrology_pi_parameters(), fmu);
}

// Starts the fixture from `fmu` as the metrology frame's PI (`edit` applied to the settings); the
// InputError's message, or "" when it started.
template <class Edit>
std::string start_refusal(const std::string& fmu, Edit edit) {
  auto s = pi_settings(fmu);
  edit(s);
  return flexloop::test::input_error_of([&] { (void)FmuController::from_settings(s); });
}
std::string start_refusal(const std::string& fmu) {
  return start_refusal(fmu, [](auto&) {});
}

}  // namespace

TEST_CASE("An FMU that needs its execution tool is refused with the reason", "[fmu][description]") {
  PrivateTmpdir t;
  const auto f =
      described_fmu(t, "tool.fmu", "<CoSimulation ", "<CoSimulation needsExecutionTool=\"true\" ");
  CHECK(start_refusal(f) ==
        f + ": needsExecutionTool=\"true\": the FMU runs only inside the tool that exported it, "
            "which flexloop does not start; export a standalone (tool-independent) Co-Simulation "
            "FMU");
  CHECK(start_refusal(described_fmu(t, "no_tool.fmu", "<CoSimulation ",
                                    "<CoSimulation needsExecutionTool=\"false\" "))
            .empty());
  CHECK(t.left_behind().empty());
}

TEST_CASE("A variable without a valueReference, or with a bad one, is refused naming it",
          "[fmu][description]") {
  PrivateTmpdir t;
  // y1 is the first variable; valueReference="0" is its value reference.
  const auto missing =
      described_fmu(t, "no_vr.fmu", "name=\"y1\" valueReference=\"0\"", "name=\"y1\"");
  CHECK(start_refusal(missing) == missing +
                                      ": modelDescription.xml: variable 'y1' has no "
                                      "valueReference (the standard requires one)");
  for (const std::string bad : {"-1", "x", "4294967296", ""}) {
    const auto f = described_fmu(t, "bad_vr.fmu", "name=\"y1\" valueReference=\"0\"",
                                 "name=\"y1\" valueReference=\"" + bad + "\"");
    CHECK(start_refusal(f) == f + ": modelDescription.xml: variable 'y1' has valueReference \"" +
                                  bad + "\", not an unsigned 32-bit integer");
  }
  CHECK(t.left_behind().empty());
}

TEST_CASE("A mapped variable of the wrong causality, variability or type is refused naming it",
          "[fmu][description]") {
  PrivateTmpdir t;
  const auto f = flexloop::test::pi_fmu_path();
  // A sensor mapped to an output, an actuator to a parameter.
  CHECK(start_refusal(f, [](auto& s) { s.inputs[0] = "u1"; }) ==
        f + ": variable 'u1' is a real output, not a real input");
  CHECK(start_refusal(f, [](auto& s) { s.outputs[2] = "K_P_1_1"; }) ==
        f + ": variable 'K_P_1_1' is a real parameter, not a real output");
  // A parameter the scene sets must be fixed or tunable (FMI 2.0: a parameter is one of them).
  const auto continuous = described_fmu(
      t, "continuous.fmu",
      "name=\"K_P_1_1\" valueReference=\"12\" causality=\"parameter\" variability=\"fixed\"",
      "name=\"K_P_1_1\" valueReference=\"12\" causality=\"parameter\" variability=\"continuous\"");
  CHECK(start_refusal(continuous) ==
        continuous +
            ": variable 'K_P_1_1' is a real parameter of variability \"continuous\": "
            "flexloop sets parameters of variability \"fixed\" or \"tunable\" only");
  const auto tunable = described_fmu(
      t, "tunable.fmu",
      "name=\"K_P_1_1\" valueReference=\"12\" causality=\"parameter\" variability=\"fixed\"",
      "name=\"K_P_1_1\" valueReference=\"12\" causality=\"parameter\" variability=\"tunable\"");
  CHECK(start_refusal(tunable).empty());
  // y1 an Integer (its <Real> is the first in the file).
  const auto integer =
      described_fmu(t, "integer.fmu", "<Real start=\"0\"/>", "<Integer start=\"0\"/>");
  CHECK(start_refusal(integer) ==
        integer + ": variable 'y1' is an Integer input, not a real input");
  CHECK(t.left_behind().empty());
}

TEST_CASE("A modelIdentifier that is not a C identifier is refused", "[fmu][description]") {
  PrivateTmpdir t;
  for (const std::string id : {"pi-force-feedback", "../../tmp/x", "/tmp/x", "1pi", "pi force"}) {
    const auto f = described_fmu(t, "id.fmu", "modelIdentifier=\"pi_force_feedback\"",
                                 "modelIdentifier=\"" + id + "\"");
    CHECK(start_refusal(f) == f + ": modelDescription.xml: modelIdentifier \"" + id +
                                  "\" is not a C identifier ([A-Za-z_][A-Za-z0-9_]*): it names "
                                  "the library binaries/linux64/<modelIdentifier>.so");
  }
  CHECK(t.left_behind().empty());
}

TEST_CASE("A library outside the archive is never loaded: its constructor does not run",
          "[fmu][description]") {
  PrivateTmpdir t;
  // The loader unpacks into <root>/tmp/flexloop-fmu-XXXXXX: from binaries/linux64 there,
  // "../../../../x" is <root>/x, where the marker library waits; so does "<root>/x".
  const fs::path outside = t.root.path / "x.so", marker = t.root.path / "x.so.loaded";
  fs::copy_file(FLEXLOOP_LOAD_MARKER_LIBRARY, outside);
  for (const std::string& id : {std::string("../../../../x"), (t.root.path / "x").string()}) {
    const auto f = described_fmu(t, "outside.fmu", "modelIdentifier=\"pi_force_feedback\"",
                                 "modelIdentifier=\"" + id + "\"");
    CHECK_THAT(start_refusal(f),
               Catch::StartsWith(f + ": modelDescription.xml: modelIdentifier \"" + id +
                                 "\" is not a C identifier"));
    // The loader's own check, given such a description directly.
    const flexloop::controller::fmu::FmuDirectory unpacked(f);
    FmuDescription d;
    d.model_identifier = id;
    d.guid = "{outside}";
    CHECK(flexloop::test::input_error_of([&] {
            const FmuLibrary library(unpacked.path(), d, f);
          }) == f + ": modelIdentifier \"" + id +
                    "\" is not a C identifier ([A-Za-z_][A-Za-z0-9_]*): no library is "
                    "loaded for it");
    CHECK_FALSE(fs::exists(marker));
  }
  // A valid identifier whose library is a link out of the folder: its canonical path is outside.
  const fs::path folder = t.inputs / "linked";
  fs::create_directories(folder / "binaries/linux64");
  fs::create_symlink(outside, folder / "binaries/linux64/x.so");
  FmuDescription d;
  d.model_identifier = "x";
  d.guid = "{linked}";
  CHECK(flexloop::test::input_error_of([&] {
          const FmuLibrary library(folder, d, "linked.fmu");
        }) == "linked.fmu: binaries/linux64/x.so resolves to " + fs::canonical(outside).string() +
                  ", outside the FMU's unpacked folder: not loaded");
  CHECK_FALSE(fs::exists(marker));
  CHECK(t.left_behind().empty());
  // The marker library does write its marker when it is loaded: the checks above mean something.
  void* loaded = dlopen(outside.c_str(), RTLD_NOW | RTLD_LOCAL);
  REQUIRE(loaded);
  CHECK(fs::exists(marker));
  dlclose(loaded);
}

TEST_CASE("A library of another types platform or FMI version is refused before instantiation",
          "[fmu][description]") {
  PrivateTmpdir t;
  const std::string same = "modelIdentifier=\"pi_force_feedback\"";
  const auto platform =
      described_fmu(t, "platform.fmu", same, same, FLEXLOOP_PI_OTHER_PLATFORM_LIBRARY);
  CHECK(start_refusal(platform) ==
        platform +
            ": its fmi2GetTypesPlatform returns \"standard32\", not \"default\": flexloop "
            "passes the standard's default types (fmi2Real double, fmi2ValueReference "
            "unsigned int)");
  const auto version =
      described_fmu(t, "version.fmu", same, same, FLEXLOOP_PI_OTHER_VERSION_LIBRARY);
  CHECK(start_refusal(version) ==
        version +
            ": its fmi2GetVersion returns \"1.0\", not \"2.0\": flexloop calls FMI 2.0 "
            "functions");
  CHECK(t.left_behind().empty());
}

TEST_CASE("An FMU that can be instantiated only once per process runs once at a time",
          "[fmu][description]") {
  PrivateTmpdir t;
  const auto once = described_fmu(t, "once.fmu", "canBeInstantiatedOnlyOncePerProcess=\"false\"",
                                  "canBeInstantiatedOnlyOncePerProcess=\"true\"");
  {
    const auto first = FmuController::from_settings(pi_settings(once));
    CHECK(start_refusal(once) ==
          once +
              ": canBeInstantiatedOnlyOncePerProcess=\"true\" and this process already runs "
              "an instance of it (guid {5f1d8c2e-33a0-4b6e-9d1c-pi-force-feedback-1}): one "
              "instance per process");
    // The fixture as it is (false) runs beside it: the claim is the once-only FMU's alone.
    CHECK(start_refusal(flexloop::test::pi_fmu_path()).empty());
  }
  CHECK(start_refusal(once).empty());  // the first one has gone
  // Without the attribute, two instances run at once.
  const auto f = flexloop::test::pi_fmu_path();
  const auto a = FmuController::from_settings(pi_settings(f));
  CHECK(start_refusal(f).empty());
  CHECK(t.left_behind().size() == 1);  // a's folder, while a lives
}
