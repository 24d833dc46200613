// SPDX-License-Identifier: BSD-3-Clause
// The exported plant FMU (`flexloop export-fmu`) against the FMI 2.0 standard's rules for the
// calls (modelica/fmi-standard v2.0.5, section 4.2.4's table; section 2.1.5 for the logging): each
// call in a state the table forbids, a get or set naming a variable its state does not allow, a
// null array, an unknown log category and a communication point other than the FMU's time are
// refused with fmi2Error and a logged reason, and leave the instance in the error state until
// fmi2Reset. The library is the one every exported FMU carries, loaded as a master loads it.
#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <pugixml.hpp>
#include <set>
#include <string>
#include <vector>

#include "common/fmi2.h"
#include "controller/fmu/fmu_archive.hpp"
#include "offline/pipeline/plant_fmu_export.hpp"
#include "offline/pipeline/si_unit.hpp"
#include "offline/scene/loop_input.hpp"
#include "tests/fmu/fmu_fixture.hpp"

using namespace flexloop;

namespace plant_fmu_calls {

struct Message {
  fmi2Status status;
  std::string category, text;
};

// The master's logger: every message, formatted.
void logger(fmi2ComponentEnvironment env, fmi2String, fmi2Status status, fmi2String category,
            fmi2String message, ...) {
  char text[2048];
  va_list args;
  va_start(args, message);
  std::vsnprintf(text, sizeof text, message, args);
  va_end(args);
  static_cast<std::vector<Message>*>(env)->push_back({status, category ? category : "", text});
}

using Instantiate = fmi2Component(fmi2String, fmi2Type, fmi2String, fmi2String,
                                  const fmi2CallbackFunctions*, fmi2Boolean, fmi2Boolean);
using Call = fmi2Status(fmi2Component);
using SetupExperiment = fmi2Status(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean,
                                   fmi2Real);
using GetReal = fmi2Status(fmi2Component, const fmi2ValueReference[], size_t, fmi2Real[]);
using SetReal = fmi2Status(fmi2Component, const fmi2ValueReference[], size_t, const fmi2Real[]);
using GetBoolean = fmi2Status(fmi2Component, const fmi2ValueReference[], size_t, fmi2Boolean[]);
using SetBoolean = fmi2Status(fmi2Component, const fmi2ValueReference[], size_t,
                              const fmi2Boolean[]);
using GetInteger = fmi2Status(fmi2Component, const fmi2ValueReference[], size_t, fmi2Integer[]);
using DoStep = fmi2Status(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);
using SetDebugLogging = fmi2Status(fmi2Component, fmi2Boolean, size_t, const fmi2String[]);

template <class F>
F* resolve(void* handle, const char* name) {
  auto* f = reinterpret_cast<F*>(dlsym(handle, name));
  INFO(name);
  REQUIRE(f);
  return f;
}

// An exported plant FMU, unpacked and its library loaded, with one instance at a time.
class PlantFmu {
 public:
  explicit PlantFmu(const artefact::LoopArtefact& a)
      : loop_(a), file_(export_into(a, dir_.path)), unpacked_(file_) {
    const auto so = unpacked_.path() / "binaries/linux64/flexloop_plant.so";
    handle_ = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
    REQUIRE(handle_);
    instantiate_ = resolve<Instantiate>(handle_, "fmi2Instantiate");
    free_ = resolve<void(fmi2Component)>(handle_, "fmi2FreeInstance");
    setup = resolve<SetupExperiment>(handle_, "fmi2SetupExperiment");
    enter = resolve<Call>(handle_, "fmi2EnterInitializationMode");
    exit = resolve<Call>(handle_, "fmi2ExitInitializationMode");
    terminate = resolve<Call>(handle_, "fmi2Terminate");
    reset = resolve<Call>(handle_, "fmi2Reset");
    get_real = resolve<GetReal>(handle_, "fmi2GetReal");
    set_real = resolve<SetReal>(handle_, "fmi2SetReal");
    get_boolean = resolve<GetBoolean>(handle_, "fmi2GetBoolean");
    set_boolean = resolve<SetBoolean>(handle_, "fmi2SetBoolean");
    get_integer = resolve<GetInteger>(handle_, "fmi2GetInteger");
    do_step = resolve<DoStep>(handle_, "fmi2DoStep");
    set_debug_logging = resolve<SetDebugLogging>(handle_, "fmi2SetDebugLogging");
    pugi::xml_document doc;
    REQUIRE(doc.load_file((unpacked_.path() / "modelDescription.xml").c_str()));
    guid_ = doc.child("fmiModelDescription").attribute("guid").value();
    for (auto c : doc.child("fmiModelDescription").child("LogCategories").children("Category"))
      declared_categories.insert(c.attribute("name").value());
  }
  ~PlantFmu() {
    if (c) free_(c);
    dlclose(handle_);
  }

  /// fmi2Instantiate's answer for this name and type, with the FMU's GUID and resources.
  fmi2Component try_instantiate(const char* name, fmi2Type type, bool logging_on = false) {
    const std::string resources = "file://" + (unpacked_.path() / "resources").string();
    return instantiate_(name, type, guid_.c_str(), resources.c_str(), &callbacks_, fmi2False,
                        logging_on ? fmi2True : fmi2False);
  }
  /// A new instance (the previous one freed), in state instantiated.
  void instantiate(bool logging_on = false) {
    if (c) free_(c);
    c = try_instantiate("calls", fmi2CoSimulation, logging_on);
    REQUIRE(c);
  }
  /// Instantiated, set up and initialised: stepComplete at t = 0.
  void start() {
    instantiate();
    REQUIRE(setup(c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
    REQUIRE(enter(c) == fmi2OK);
    REQUIRE(exit(c) == fmi2OK);
  }
  /// The call was refused, and the last message says why, under logStatusError.
  void refused(fmi2Status status, const std::string& says) {
    CHECK(status == fmi2Error);
    REQUIRE_FALSE(log.empty());
    INFO(log.back().text);
    CHECK(log.back().status == fmi2Error);
    CHECK(log.back().category == "logStatusError");
    CHECK(log.back().text.find(says) != std::string::npos);
  }
  double h() const { return loop_.dt(); }
  fmi2ValueReference input() const { return 0; }
  fmi2ValueReference output() const { return static_cast<fmi2ValueReference>(loop_.actuators()); }
  std::vector<fmi2ValueReference> outputs() const {
    std::vector<fmi2ValueReference> vr;
    for (Eigen::Index i = 0; i < loop_.sensors() + loop_.performance(); ++i)
      vr.push_back(output() + static_cast<fmi2ValueReference>(i));
    return vr;
  }

  fmi2Component c = nullptr;
  std::vector<Message> log;
  std::set<std::string> declared_categories;
  SetupExperiment* setup;
  Call *enter, *exit, *terminate, *reset;
  GetReal* get_real;
  SetReal* set_real;
  GetBoolean* get_boolean;
  SetBoolean* set_boolean;
  GetInteger* get_integer;
  DoStep* do_step;
  SetDebugLogging* set_debug_logging;

 private:
  static std::string export_into(const artefact::LoopArtefact& a, const std::filesystem::path& d) {
    const auto fmu = d / "plant.fmu";
    pipeline::export_plant_fmu(a, FLEXLOOP_PLANT_FMU_LIBRARY, fmu);
    return fmu.string();
  }

  artefact::LoopArtefact loop_;
  test::TemporaryDirectory dir_;
  std::string file_;
  controller::fmu::FmuDirectory unpacked_;
  void* handle_ = nullptr;
  Instantiate* instantiate_;
  void (*free_)(fmi2Component);
  std::string guid_;
  fmi2CallbackFunctions callbacks_{logger, nullptr, nullptr, nullptr, &log};
};

const artefact::LoopArtefact& chain() {
  static const auto a = scene::load_loop("tools/scenes/two_mass_chain.toml");
  return a;
}

}  // namespace plant_fmu_calls

using plant_fmu_calls::PlantFmu;

TEST_CASE("The plant FMU's fmi2DoStep checks the communication point against its own time",
          "[fmu]") {
  PlantFmu fmu(plant_fmu_calls::chain());
  const double h = fmu.h();
  fmu.start();
  REQUIRE(fmu.do_step(fmu.c, 0, h, fmi2True) == fmi2OK);
  // A master that repeats t = 0: the FMU is at h. The message names both times.
  fmu.refused(fmu.do_step(fmu.c, 0, h, fmi2True), "currentCommunicationPoint 0 s");
  char expected[64];
  std::snprintf(expected, sizeof expected, "the FMU's time %.17g s", h);
  CHECK(fmu.log.back().text.find(expected) != std::string::npos);
  // The instance is in the error state: the right point is refused too, until fmi2Reset.
  fmu.refused(fmu.do_step(fmu.c, h, h, fmi2True), "fmi2DoStep is not allowed in state error");
  CHECK(fmu.reset(fmu.c) == fmi2OK);
  CHECK(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);

  fmu.start();  // a point a millionth of a step off, and half a step off
  fmu.refused(fmu.do_step(fmu.c, 1e-6 * h, h, fmi2True), "is not the FMU's time");
  fmu.start();
  REQUIRE(fmu.do_step(fmu.c, 0, h, fmi2True) == fmi2OK);
  fmu.refused(fmu.do_step(fmu.c, 1.5 * h, h, fmi2True), "is not the FMU's time");
  fmu.start();  // a step size other than the period
  fmu.refused(fmu.do_step(fmu.c, 0, 2 * h, fmi2True), "communicationStepSize");

  // A master that adds h to its time, 2 s at 10 kHz: its points drift from k h by rounding, and
  // every one is accepted.
  fmu.start();
  double t = 0;
  long drifted = 0;
  for (long k = 0; k < 20000; ++k) {
    drifted += t != static_cast<double>(k) * h;
    REQUIRE(fmu.do_step(fmu.c, t, h, fmi2True) == fmi2OK);
    t += h;
  }
  CHECK(drifted > 1000);
}

TEST_CASE("The plant FMU allows each call only in the states FMI 2.0 allows it", "[fmu]") {
  PlantFmu fmu(plant_fmu_calls::chain());
  const fmi2ValueReference in = fmu.input(), out = fmu.output(), rest = 0;
  const double one = 1;
  double value = 0;
  fmi2Boolean flag = fmi2False;
  const fmi2Boolean yes = fmi2True;

  // instantiated: no real variable may be set (inputs have no initial attribute) or read; the
  // fixed parameter may be set, not read; no step, no exit, no terminate.
  fmu.instantiate();
  fmu.refused(fmu.get_real(fmu.c, &out, 1, &value),
              "fmi2GetReal is not allowed in state instantiated");
  fmu.instantiate();
  fmu.refused(fmu.set_real(fmu.c, &in, 1, &one),
              "fmi2SetReal is not allowed in state instantiated");
  fmu.instantiate();
  CHECK(fmu.set_boolean(fmu.c, &rest, 1, &yes) == fmi2OK);
  fmu.refused(fmu.get_boolean(fmu.c, &rest, 1, &flag), "state instantiated");
  for (auto* call : {fmu.exit, fmu.terminate}) {
    fmu.instantiate();
    fmu.refused(call(fmu.c), "is not allowed in state instantiated");
  }
  fmu.instantiate();
  fmu.refused(fmu.setup(fmu.c, fmi2False, 0, 1, fmi2False, 0), "not at startTime 1");
  fmu.instantiate();
  fmu.refused(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2True, -1), "stopTime -1 is before startTime 0");
  fmu.instantiate();
  fmu.refused(fmu.do_step(fmu.c, 0, fmu.h(), fmi2True),
              "fmi2DoStep is not allowed in state instantiated");

  // initializationMode: outputs read, inputs set; not an input read, not the parameter read.
  fmu.instantiate();
  REQUIRE(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  CHECK(fmu.set_real(fmu.c, &in, 1, &one) == fmi2OK);
  CHECK(fmu.get_real(fmu.c, &out, 1, &value) == fmi2OK);
  fmu.refused(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2False, 0),
              "fmi2SetupExperiment is not allowed in state initializationMode");
  CHECK(fmu.reset(fmu.c) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  fmu.refused(fmu.get_real(fmu.c, &in, 1, &value), "is an input");
  CHECK(fmu.reset(fmu.c) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  fmu.refused(fmu.get_boolean(fmu.c, &rest, 1, &flag), "state initializationMode");
  CHECK(fmu.reset(fmu.c) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  fmu.refused(fmu.do_step(fmu.c, 0, fmu.h(), fmi2True), "state initializationMode");

  // stepComplete: inputs set, not outputs, not the fixed parameter; no get after a set without a
  // step between; not initialised again.
  fmu.start();
  fmu.refused(fmu.set_real(fmu.c, &out, 1, &one), "is an output");
  fmu.start();
  fmu.refused(fmu.set_boolean(fmu.c, &rest, 1, &yes), "state stepComplete");
  fmu.start();
  fmu.refused(fmu.enter(fmu.c), "fmi2EnterInitializationMode is not allowed in state stepComplete");
  fmu.start();
  CHECK(fmu.set_real(fmu.c, &in, 1, &one) == fmi2OK);
  fmu.refused(fmu.get_real(fmu.c, &out, 1, &value), "without an fmi2DoStep between");
  fmu.start();
  CHECK(fmu.set_real(fmu.c, &in, 1, &one) == fmi2OK);
  CHECK(fmu.do_step(fmu.c, 0, fmu.h(), fmi2True) == fmi2OK);
  CHECK(fmu.get_real(fmu.c, &in, 1, &value) == fmi2OK);
  CHECK(value == one);

  // terminated: values read; no set, no step, no second terminate; fmi2Reset starts again.
  double last = 0;
  CHECK(fmu.get_real(fmu.c, &out, 1, &last) == fmi2OK);
  CHECK(fmu.terminate(fmu.c) == fmi2OK);
  CHECK(fmu.get_real(fmu.c, &out, 1, &value) == fmi2OK);
  CHECK(value == last);
  CHECK(fmu.get_boolean(fmu.c, &rest, 1, &flag) == fmi2OK);
  CHECK(fmu.set_real(fmu.c, &in, 1, &one) == fmi2Error);
  CHECK(fmu.log.back().text.find("fmi2SetReal is not allowed in state terminated") !=
        std::string::npos);
  CHECK(fmu.reset(fmu.c) == fmi2OK);
  CHECK(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
  for (auto* call : {fmu.terminate, fmu.enter, fmu.exit}) {
    fmu.start();
    REQUIRE(fmu.terminate(fmu.c) == fmi2OK);
    fmu.refused(call(fmu.c), "is not allowed in state terminated");
  }
  fmu.start();
  REQUIRE(fmu.terminate(fmu.c) == fmi2OK);
  fmu.refused(fmu.do_step(fmu.c, fmu.h(), fmu.h(), fmi2True), "state terminated");

  // error: values may be read (for debugging), nothing else goes on.
  CHECK(fmu.get_real(fmu.c, &out, 1, &value) == fmi2OK);
  fmu.refused(fmu.set_real(fmu.c, &in, 1, &one), "state error");
  fmu.refused(fmu.terminate(fmu.c), "state error");

  // No instance: every call refuses, none crashes.
  CHECK(fmu.get_real(nullptr, &out, 1, &value) == fmi2Error);
  CHECK(fmu.set_real(nullptr, &in, 1, &one) == fmi2Error);
  CHECK(fmu.do_step(nullptr, 0, fmu.h(), fmi2True) == fmi2Error);
  CHECK(fmu.reset(nullptr) == fmi2Error);
  CHECK(fmu.set_debug_logging(nullptr, fmi2True, 0, nullptr) == fmi2Error);
}

TEST_CASE(
    "The plant FMU's outputs in initialization mode are the sample at t = 0, whatever the "
    "inputs (its ModelStructure lists no dependency)",
    "[fmu]") {
  PlantFmu fmu(plant_fmu_calls::chain());
  const auto out = fmu.outputs();
  const fmi2ValueReference in = fmu.input();
  std::vector<double> before(out.size()), after(out.size()), stepping(out.size());
  fmu.instantiate();
  REQUIRE(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  REQUIRE(fmu.get_real(fmu.c, out.data(), out.size(), before.data()) == fmi2OK);
  const double large = 1e3;
  REQUIRE(fmu.set_real(fmu.c, &in, 1, &large) == fmi2OK);
  REQUIRE(fmu.get_real(fmu.c, out.data(), out.size(), after.data()) == fmi2OK);
  REQUIRE(fmu.exit(fmu.c) == fmi2OK);
  REQUIRE(fmu.get_real(fmu.c, out.data(), out.size(), stepping.data()) == fmi2OK);
  CHECK(after == before);
  CHECK(stepping == before);
  double largest = 0;
  for (double v : before) largest = std::max(largest, std::abs(v));
  CHECK(largest > 0);  // the stationary start: a draw, not zeros

  // start_at_rest set in initialization mode after the outputs were read: they are the sample at
  // rest, as when it is set before.
  const fmi2ValueReference rest = 0;
  const fmi2Boolean yes = fmi2True;
  std::vector<double> late(out.size()), early(out.size());
  fmu.instantiate();
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  REQUIRE(fmu.get_real(fmu.c, out.data(), out.size(), late.data()) == fmi2OK);
  CHECK(late == before);
  REQUIRE(fmu.set_boolean(fmu.c, &rest, 1, &yes) == fmi2OK);
  REQUIRE(fmu.exit(fmu.c) == fmi2OK);
  REQUIRE(fmu.get_real(fmu.c, out.data(), out.size(), late.data()) == fmi2OK);
  fmu.instantiate();
  REQUIRE(fmu.set_boolean(fmu.c, &rest, 1, &yes) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  REQUIRE(fmu.exit(fmu.c) == fmi2OK);
  REQUIRE(fmu.get_real(fmu.c, out.data(), out.size(), early.data()) == fmi2OK);
  CHECK(late == early);
  CHECK(late != before);
}

TEST_CASE("The plant FMU refuses null arguments without reading them", "[fmu]") {
  PlantFmu fmu(plant_fmu_calls::chain());
  CHECK(fmu.try_instantiate(nullptr, fmi2CoSimulation) == nullptr);
  CHECK(fmu.log.back().text == "fmi2Instantiate: no instanceName");
  CHECK(fmu.try_instantiate("", fmi2CoSimulation) == nullptr);
  CHECK(fmu.log.back().text == "fmi2Instantiate: no instanceName");
  CHECK(fmu.try_instantiate("me", fmi2ModelExchange) == nullptr);
  CHECK(fmu.log.back().text.find("Co-Simulation only") != std::string::npos);
  const fmi2ValueReference vr[2] = {0, 0};
  double values[2] = {0, 0};
  fmi2Boolean flags[2] = {0, 0};
  fmi2Integer integers[2] = {0, 0};
  fmu.start();
  CHECK(fmu.get_real(fmu.c, nullptr, 0, nullptr) == fmi2OK);  // nothing asked: nothing read
  CHECK(fmu.set_real(fmu.c, nullptr, 0, nullptr) == fmi2OK);
  fmu.start();
  fmu.refused(fmu.get_real(fmu.c, nullptr, 2, values), "fmi2GetReal: nvr = 2 with a null vr array");
  fmu.start();
  fmu.refused(fmu.get_real(fmu.c, vr, 2, nullptr), "with a null value array");
  fmu.start();
  fmu.refused(fmu.set_real(fmu.c, nullptr, 2, values), "fmi2SetReal: nvr = 2 with a null vr");
  fmu.start();
  fmu.refused(fmu.set_real(fmu.c, vr, 1, nullptr), "fmi2SetReal: nvr = 1 with a null value");
  fmu.start();
  fmu.refused(fmu.get_boolean(fmu.c, nullptr, 1, flags), "fmi2GetBoolean: nvr = 1 with a null");
  fmu.instantiate();
  fmu.refused(fmu.set_boolean(fmu.c, vr, 1, nullptr), "fmi2SetBoolean: nvr = 1 with a null");
  fmu.start();
  fmu.refused(fmu.get_integer(fmu.c, nullptr, 1, integers), "fmi2GetInteger: nvr = 1 with a null");
  fmu.start();
  fmu.refused(fmu.set_debug_logging(fmu.c, fmi2True, 1, nullptr),
              "nCategories = 1 with a null categories array");
  // A value reference outside the variables, and a variable of a type the FMU does not have.
  fmu.start();
  const fmi2ValueReference beyond = 1000;
  fmu.refused(fmu.get_real(fmu.c, &beyond, 1, values), "no real variable has value reference 1000");
  fmu.start();
  fmu.refused(fmu.get_integer(fmu.c, vr, 1, integers), "no integer variables");
}

TEST_CASE(
    "The plant FMU logs under the categories its description declares, as the master sets "
    "them",
    "[fmu]") {
  PlantFmu fmu(plant_fmu_calls::chain());
  REQUIRE(fmu.declared_categories == std::set<std::string>{"logStatusError", "logEvents"});
  // loggingOn: the events too.
  fmu.instantiate(true);
  REQUIRE(fmu.setup(fmu.c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
  REQUIRE(fmu.enter(fmu.c) == fmi2OK);
  REQUIRE(fmu.exit(fmu.c) == fmi2OK);
  REQUIRE(fmu.terminate(fmu.c) == fmi2OK);
  long events = 0;
  for (const auto& m : fmu.log) {
    INFO(m.category << ": " << m.text);
    CHECK(fmu.declared_categories.count(m.category) == 1);
    events += m.category == "logEvents" && m.status == fmi2OK;
  }
  CHECK(events >= 3);  // instantiated, initialised, terminated

  // An unknown category is refused and changes nothing.
  fmu.start();
  const fmi2String unknown[] = {"logEvents", "logEverything"};
  fmu.refused(fmu.set_debug_logging(fmu.c, fmi2False, 2, unknown),
              "\"logEverything\" is not a log category");

  // Errors off: a refused call says nothing; on again by name: it does.
  fmu.start();
  const std::size_t before = fmu.log.size();
  CHECK(fmu.set_debug_logging(fmu.c, fmi2False, 0, nullptr) == fmi2OK);
  CHECK(fmu.enter(fmu.c) == fmi2Error);
  CHECK(fmu.log.size() == before);
  const fmi2String errors[] = {"logStatusError"};
  CHECK(fmu.set_debug_logging(fmu.c, fmi2True, 1, errors) == fmi2OK);
  fmu.refused(fmu.enter(fmu.c), "fmi2EnterInitializationMode is not allowed in state error");
  // loggingOn = false: no events, and errors still said.
  fmu.log.clear();
  fmu.start();
  CHECK(fmu.log.empty());
  fmu.refused(fmu.enter(fmu.c), "fmi2EnterInitializationMode is not allowed in state stepComplete");
}

TEST_CASE("A channel's SI unit reads into FMI 2.0 base-unit exponents and a Modelica name",
          "[fmu]") {
  using pipeline::parse_si_unit;
  using E = std::array<int, 8>;  // kg m s A K mol cd rad
  const struct {
    const char* text;
    const char* name;
    E exponents;
  } cases[] = {
      {"m/s^2", "m/s2", {0, 1, -2, 0, 0, 0, 0, 0}},
      {"rad/s^2", "rad/s2", {0, 0, -2, 0, 0, 0, 0, 1}},
      {"m/s", "m/s", {0, 1, -1, 0, 0, 0, 0, 0}},
      {"rad/s", "rad/s", {0, 0, -1, 0, 0, 0, 0, 1}},
      {"m", "m", {0, 1, 0, 0, 0, 0, 0, 0}},
      {"rad", "rad", {0, 0, 0, 0, 0, 0, 0, 1}},
      {"N", "N", {1, 1, -2, 0, 0, 0, 0, 0}},
      {"N m", "N.m", {1, 2, -2, 0, 0, 0, 0, 0}},
      {"kg.m2/s2", "kg.m2/s2", {1, 2, -2, 0, 0, 0, 0, 0}},
      {"m s^-2", "m.s-2", {0, 1, -2, 0, 0, 0, 0, 0}},
      {"1/s", "1/s", {0, 0, -1, 0, 0, 0, 0, 0}},
      {"1", "1", {0, 0, 0, 0, 0, 0, 0, 0}},
      {"N/(m*s)", "N/(m.s)", {1, 0, -3, 0, 0, 0, 0, 0}},
      {"V", "V", {1, 2, -3, -1, 0, 0, 0, 0}},
  };
  for (const auto& c : cases) {
    INFO(c.text);
    const auto u = parse_si_unit(c.text);
    CHECK(u.name == c.name);
    CHECK(u.exponents == c.exponents);
  }
  for (const char* bad : {"", "furlong", "mm", "m/s^", "m//s", "m/(s", "N-m", "m s^0", "1 m"}) {
    INFO(bad);
    CHECK_THROWS_WITH(parse_si_unit(bad),
                      Catch::Contains(std::string("unit \"") + bad + "\" does not read"));
  }
}

TEST_CASE("export-fmu refuses an artefact whose channel unit does not read, naming it", "[fmu]") {
  auto a = plant_fmu_calls::chain();
  a.channels.sensors.back().unit = "furlong/s";
  test::TemporaryDirectory dir;
  CHECK_THROWS_WITH(pipeline::export_plant_fmu(a, FLEXLOOP_PLANT_FMU_LIBRARY, dir.path / "p.fmu"),
                    Catch::Contains(a.source) &&
                        Catch::Contains("sensor." + a.channels.sensors.back().name) &&
                        Catch::Contains("unknown symbol \"furlong\""));
  CHECK(std::filesystem::is_empty(dir.path));
}
