// SPDX-License-Identifier: BSD-3-Clause
// The FMI 2.0 Co-Simulation functions of the plant FMU that `flexloop export-fmu` writes
// (issue 33). The one library serves every exported machine: fmi2Instantiate reads the loop
// artefact from the FMU's resources/ (written beside the GUID it was exported with), and the
// variables are plant_fmu_variables.hpp's. One fmi2DoStep(t, h) is one loop period h = 1 / rate:
// the command set before it is held over [t, t + h), the plant advances, and the outputs are the
// sample at t + h -- the convention of `flexloop sim` (online/sim/closed_loop_run.hpp), so that a
// master that reads the outputs, computes its command, sets it and steps runs sim's loop.
//
// Every call checks its arguments (null pointers first), then the FMI 2.0 Co-Simulation state
// machine (the standard's section 4.2.4: which call in which state, and which variables a get or
// set may name there). A refused call returns fmi2Error, logs why under "logStatusError", and
// leaves the instance in the state `error`, from which fmi2Reset starts it again (section 2.1.3:
// after fmi2Error the simulation cannot continue with the instance). No exception leaves this
// file. Messages are formatted into a buffer on the stack: no refusal allocates, and fmi2DoStep,
// fmi2GetReal and fmi2SetReal in stepComplete neither allocate nor log unless they refuse.
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/fmi2.h"
#include "online/plant_fmu/plant_fmu_model.hpp"
#include "online/plant_fmu/plant_fmu_variables.hpp"

namespace {

namespace pf = flexloop::plant_fmu;

// The states of the standard's state machine this FMU reaches, as bits so that a call names the
// states it is allowed in. Its steps are synchronous and never discarded: stepInProgress,
// stepFailed, stepCanceled and fatal do not arise.
enum State : unsigned {
  kInstantiated = 1u << 0,
  kInitializationMode = 1u << 1,
  kStepComplete = 1u << 2,
  kTerminated = 1u << 3,
  kError = 1u << 4,
};
constexpr unsigned kEveryState =
    kInstantiated | kInitializationMode | kStepComplete | kTerminated | kError;
// fmi2GetXXX (the table's "2": outputs only in initialization mode; "7": values in the error
// state are for debugging) and fmi2SetXXX ("1", "3", "6": which variables, checked per call).
constexpr unsigned kGetStates = kInitializationMode | kStepComplete | kTerminated | kError;
constexpr unsigned kSetStates = kInstantiated | kInitializationMode | kStepComplete;

const char* state_name(unsigned s) {
  switch (s) {
    case kInstantiated:
      return "instantiated";
    case kInitializationMode:
      return "initializationMode";
    case kStepComplete:
      return "stepComplete";
    case kTerminated:
      return "terminated";
    default:
      return "error";
  }
}

struct PlantInstance {
  std::string name;
  fmi2CallbackLogger logger = nullptr;  // the master's, kept (its struct may not outlive the call)
  fmi2ComponentEnvironment environment = nullptr;
  std::array<bool, pf::kLogCategoryCount> logging{};  // by pf::kLogCategories
  flexloop::artefact::LoopArtefact loop;
  std::unique_ptr<pf::PlantFmuModel> model;  // from initialization mode on, outputs at t = 0
  std::size_t inputs = 0;
  std::vector<double> values;  // by value reference: the commands, then the readings
  bool start_at_rest = false;
  unsigned state = kInstantiated;
  long long steps = 0;          // steps done: the FMU's time is steps * h (it starts at 0)
  bool set_since_step = false;  // an fmi2SetReal in stepComplete since the last fmi2DoStep
};

PlantInstance* instance(fmi2Component c) {
  return static_cast<PlantInstance*>(c);
}

void vlog(const PlantInstance* in, fmi2Status status, std::size_t category, const char* format,
          va_list args) {
  if (!in->logging[category] || !in->logger) return;
  char text[1024];
  std::vsnprintf(text, sizeof text, format, args);
  in->logger(in->environment, in->name.c_str(), status, pf::kLogCategories[category].name, "%s",
             text);
}

// A refusal: logged under logStatusError, and the instance is in the error state.
[[gnu::format(printf, 2, 3)]] fmi2Status fail(PlantInstance* in, const char* format, ...) {
  if (!in) return fmi2Error;
  in->state = kError;
  va_list args;
  va_start(args, format);
  vlog(in, fmi2Error, pf::kLogStatusError, format, args);
  va_end(args);
  return fmi2Error;
}

[[gnu::format(printf, 2, 3)]] void event(const PlantInstance* in, const char* format, ...) {
  va_list args;
  va_start(args, format);
  vlog(in, fmi2OK, pf::kLogEvents, format, args);
  va_end(args);
}

fmi2Status wrong_state(PlantInstance* in, const char* call) {
  return fail(in, "%s is not allowed in state %s (FMI 2.0 section 4.2.4)", call,
              state_name(in->state));
}

// The arrays of a get or set: both present when it names any variable.
fmi2Status check_arrays(PlantInstance* in, const char* call, const void* vr, const void* value,
                        std::size_t n) {
  if (n > 0 && (!vr || !value))
    return fail(in, "%s: nvr = %zu with a null %s array", call, n, vr ? "value" : "vr");
  return fmi2OK;
}

// fmi2GetXXX after fmi2SetXXX with no fmi2DoStep between is not allowed in stepComplete (section
// 4.2.4): a slave's outputs change only in fmi2DoStep.
fmi2Status check_get_after_set(PlantInstance* in, const char* call) {
  if (in->state == kStepComplete && in->set_since_step)
    return fail(in,
                "%s after fmi2SetReal without an fmi2DoStep between (FMI 2.0 section 4.2.4: the "
                "outputs change only in fmi2DoStep)",
                call);
  return fmi2OK;
}

// The plant built at its start and the outputs at t = 0, once in initialization mode.
fmi2Status start_plant(PlantInstance* in, const char* call) {
  if (in->model) return fmi2OK;
  try {
    in->model = pf::PlantFmuModel::from_artefact(in->loop, in->start_at_rest);
  } catch (const std::exception& e) {
    return fail(in, "%s: the plant does not start: %s", call, e.what());
  }
  in->model->sample(in->values.data() + in->inputs);
  return fmi2OK;
}

// How far a master's step size may be from h at step k: 1e-9 h, and the rounding of a master
// that passes the difference of its points fl((k + 1) h) - fl(k h) (each rounded by half an ulp,
// <= eps t / 2, and the difference by half an ulp of h): within 2 eps t_{k+1}.
double step_tolerance(long long k, double h) {
  return 1e-9 * h + 2 * DBL_EPSILON * static_cast<double>(k + 1) * h;
}

// The drift a master's communication point may have from t_k = k h: 1e-9 h for the rounding of h,
// and what a master that adds its h k times gathers (each sum rounds by at most half an ulp,
// <= eps t_k / 2, and its h may differ by the 1e-9 h the step check accepts). Never a quarter
// step: a master that far off is at another sample.
double communication_tolerance(long long k, double h) {
  const double steps = static_cast<double>(k), t = steps * h;
  return std::min(0.25 * h, 1e-9 * h + steps * (1e-9 * h + DBL_EPSILON * t));
}

// "file:///dir" or "file:/dir" to /dir (RFC 8089; the FMI standard's resource location).
std::filesystem::path resource_directory(const char* location) {
  std::string s = location ? location : "";
  if (s.rfind("file://", 0) == 0)
    s.erase(0, 7);
  else if (s.rfind("file:", 0) == 0)
    s.erase(0, 5);
  else
    throw std::runtime_error("fmuResourceLocation \"" + s + "\" is not a file: URI");
  std::string path;  // percent-decoding: a space is %20 in a URI
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      path += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      path += s[i];
    }
  }
  return path;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::string text;
  std::getline(in, text);
  return text;
}

// The artefact the FMU's resources hold, for the GUID it was exported with.
void load(PlantInstance& in, fmi2Type type, fmi2String guid, fmi2String resources) {
  if (type != fmi2CoSimulation)
    throw std::runtime_error("this FMU is for Co-Simulation only (no Model Exchange)");
  const std::filesystem::path dir = resource_directory(resources);
  const std::string exported = read_text(dir / pf::kGuidResource);
  if (!guid || exported != guid)
    throw std::runtime_error("GUID " + std::string(guid ? guid : "(none)") + " is not this FMU's " +
                             exported);
  in.loop = flexloop::artefact::read_loop_artefact(dir / pf::kArtefactResource);
  in.inputs = static_cast<std::size_t>(in.loop.actuators());
  in.values.assign(pf::plant_fmu_variables(in.loop).size(), 0.0);
}

// The getters and setters of the types with no variable: only an empty request succeeds.
fmi2Status no_variables(fmi2Component c, const void* vr, const void* value, std::size_t n,
                        unsigned states, const char* call, const char* type) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (check_arrays(in, call, vr, value, n) != fmi2OK) return fmi2Error;
  if (!(in->state & states)) return wrong_state(in, call);
  if (n > 0)
    return fail(in, "%s: this FMU has no %s variables (value reference %u)", call, type,
                static_cast<const fmi2ValueReference*>(vr)[0]);
  return fmi2OK;
}

// The index in pf::kLogCategories of the category named, or kLogCategoryCount.
std::size_t category_index(const char* name) {
  std::size_t k = 0;
  while (k < pf::kLogCategoryCount && !(name && !std::strcmp(name, pf::kLogCategories[k].name)))
    ++k;
  return k;
}

fmi2Status unsupported(fmi2Component c, const char* call) {
  return fail(instance(c), "%s is not supported by this FMU", call);
}

}  // namespace

#define FLEXLOOP_FMI2_EXPORT extern "C" __attribute__((visibility("default")))

FLEXLOOP_FMI2_EXPORT const char* fmi2GetTypesPlatform() {
  return "default";
}
FLEXLOOP_FMI2_EXPORT const char* fmi2GetVersion() {
  return "2.0";
}

// loggingOn applies to the categories named, or to every category when none is named (section
// 2.1.5); an unknown category is refused and no setting changes.
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                                    const fmi2String categories[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (n > 0 && !categories)
    return fail(in, "fmi2SetDebugLogging: nCategories = %zu with a null categories array", n);
  std::array<bool, pf::kLogCategoryCount> named{};
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = category_index(categories[i]);
    if (k == pf::kLogCategoryCount)
      return fail(in,
                  "fmi2SetDebugLogging: \"%s\" is not a log category of this FMU (its "
                  "modelDescription.xml declares logStatusError and logEvents)",
                  categories[i] ? categories[i] : "(null)");
    named[k] = true;
  }
  for (std::size_t k = 0; k < pf::kLogCategoryCount; ++k)
    if (n == 0 || named[k]) in->logging[k] = on != fmi2False;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                                   fmi2String resources,
                                                   const fmi2CallbackFunctions* callbacks,
                                                   fmi2Boolean, fmi2Boolean logging_on) {
  if (!callbacks) return nullptr;  // no logger to say why
  try {
    auto in = std::make_unique<PlantInstance>();
    in->name = name ? name : "(no instanceName)";
    in->logger = callbacks->logger;
    in->environment = callbacks->componentEnvironment;
    in->logging[pf::kLogStatusError] = true;
    in->logging[pf::kLogEvents] = logging_on != fmi2False;
    if (!name || !*name) {
      fail(in.get(), "fmi2Instantiate: no instanceName");
      return nullptr;
    }
    try {
      load(*in, type, guid, resources);
    } catch (const std::exception& e) {
      fail(in.get(), "fmi2Instantiate: %s", e.what());
      return nullptr;
    }
    event(in.get(), "fmi2Instantiate: loop '%s', %zu plant states, step %.17g s",
          in->loop.name.c_str(), in->loop.plant.states.size(), in->loop.dt());
    return in.release();
  } catch (...) {  // out of memory: nothing to log with
    return nullptr;
  }
}

FLEXLOOP_FMI2_EXPORT void fmi2FreeInstance(fmi2Component c) {
  delete instance(c);  // allowed in every state this FMU reaches
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real,
                                                    fmi2Real start, fmi2Boolean stop_defined,
                                                    fmi2Real stop) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (in->state != kInstantiated) return wrong_state(in, "fmi2SetupExperiment");
  if (start != 0)
    return fail(in,
                "fmi2SetupExperiment: the plant starts at t = 0 (its floor and noise are seeded "
                "sequences), not at startTime %.17g",
                start);
  if (stop_defined && !(stop >= start))
    return fail(in, "fmi2SetupExperiment: stopTime %.17g is before startTime %.17g", stop, start);
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (in->state != kInstantiated) return wrong_state(in, "fmi2EnterInitializationMode");
  in->state = kInitializationMode;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (in->state != kInitializationMode) return wrong_state(in, "fmi2ExitInitializationMode");
  if (start_plant(in, "fmi2ExitInitializationMode") != fmi2OK) return fmi2Error;
  in->state = kStepComplete;
  in->steps = 0;
  in->set_since_step = false;
  event(in, "fmi2ExitInitializationMode: the outputs are the sample at t = 0 (start: %s)",
        in->start_at_rest ? "at rest" : "stationary");
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (in->state != kStepComplete) return wrong_state(in, "fmi2DoStep");
  const double dt = in->loop.dt();
  if (!(std::abs(h - dt) <= step_tolerance(in->steps, dt)))
    return fail(in,
                "fmi2DoStep: communicationStepSize %.17g s is not this plant's loop period "
                "%.17g s (its DefaultExperiment stepSize; the plant is discrete at it)",
                h, dt);
  const double expected = static_cast<double>(in->steps) * dt;
  if (!(std::abs(t - expected) <= communication_tolerance(in->steps, dt)))
    return fail(in,
                "fmi2DoStep: currentCommunicationPoint %.17g s is not the FMU's time %.17g s "
                "(step %lld of %.17g s from 0)",
                t, expected, in->steps, dt);
  in->model->apply(in->values.data());
  in->model->sample(in->values.data() + in->inputs);
  ++in->steps;
  in->set_since_step = false;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (in->state != kStepComplete) return wrong_state(in, "fmi2Terminate");
  in->state = kTerminated;
  event(in, "fmi2Terminate: after %lld steps, at t = %.17g s", in->steps,
        static_cast<double>(in->steps) * in->loop.dt());
  return fmi2OK;
}

// Back to instantiated with every variable at its start value (allowed in every state reached).
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  in->model.reset();
  std::fill(in->values.begin(), in->values.end(), 0.0);
  in->start_at_rest = false;
  in->state = kInstantiated;
  in->steps = 0;
  in->set_since_step = false;
  event(in, "fmi2Reset: instantiated again");
  return fmi2OK;
}

// Any variable in stepComplete, terminated and error; only the outputs in initialization mode
// (the table's condition 2: outputs and <InitialUnknowns>, which are the outputs).
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[],
                                            size_t n, fmi2Real value[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (check_arrays(in, "fmi2GetReal", vr, value, n) != fmi2OK) return fmi2Error;
  if (!(in->state & kGetStates)) return wrong_state(in, "fmi2GetReal");
  if (check_get_after_set(in, "fmi2GetReal") != fmi2OK) return fmi2Error;
  for (std::size_t i = 0; i < n; ++i) {
    if (vr[i] >= in->values.size())
      return fail(in, "fmi2GetReal: no real variable has value reference %u", vr[i]);
    if (in->state == kInitializationMode && vr[i] < in->inputs)
      return fail(in,
                  "fmi2GetReal: value reference %u is an input; in initializationMode only the "
                  "outputs may be read (FMI 2.0 section 4.2.4)",
                  vr[i]);
  }
  if (in->state == kInitializationMode && start_plant(in, "fmi2GetReal") != fmi2OK)
    return fmi2Error;
  for (std::size_t i = 0; i < n; ++i) value[i] = in->values[vr[i]];
  return fmi2OK;
}

// Only the inputs, in initialization mode and stepComplete (the table's conditions 3 and 6; in
// instantiated condition 1 names variables with initial = exact or approx, which no real
// variable here has). Nothing is written unless every value is.
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[],
                                            size_t n, const fmi2Real value[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (check_arrays(in, "fmi2SetReal", vr, value, n) != fmi2OK) return fmi2Error;
  if (!(in->state & (kInitializationMode | kStepComplete))) return wrong_state(in, "fmi2SetReal");
  for (std::size_t i = 0; i < n; ++i) {
    if (vr[i] >= in->values.size())
      return fail(in, "fmi2SetReal: no real variable has value reference %u", vr[i]);
    if (vr[i] >= in->inputs)
      return fail(in,
                  "fmi2SetReal: value reference %u is an output (only the actuators' commands "
                  "are inputs)",
                  vr[i]);
    if (!std::isfinite(value[i]))
      return fail(in, "fmi2SetReal: the command for value reference %u is not finite", vr[i]);
  }
  for (std::size_t i = 0; i < n; ++i) in->values[vr[i]] = value[i];
  if (in->state == kStepComplete && n > 0) in->set_since_step = true;
  return fmi2OK;
}

// start_at_rest, a parameter: not an output nor an initial unknown, so not read in initialization
// mode (condition 2).
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, fmi2Boolean value[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (check_arrays(in, "fmi2GetBoolean", vr, value, n) != fmi2OK) return fmi2Error;
  if (!(in->state & (kStepComplete | kTerminated | kError)))
    return wrong_state(in, "fmi2GetBoolean");
  if (check_get_after_set(in, "fmi2GetBoolean") != fmi2OK) return fmi2Error;
  for (std::size_t i = 0; i < n; ++i)
    if (vr[i] != pf::kStartAtRestReference)
      return fail(in, "fmi2GetBoolean: no boolean variable has value reference %u", vr[i]);
  for (std::size_t i = 0; i < n; ++i) value[i] = in->start_at_rest ? fmi2True : fmi2False;
  return fmi2OK;
}

// start_at_rest is fixed (initial = exact): set in instantiated and initialization mode
// (conditions 1 and 3), not once stepping (condition 6 asks for a tunable parameter).
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, const fmi2Boolean value[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (check_arrays(in, "fmi2SetBoolean", vr, value, n) != fmi2OK) return fmi2Error;
  if (!(in->state & (kInstantiated | kInitializationMode)))
    return wrong_state(in, "fmi2SetBoolean (start_at_rest is a fixed parameter)");
  for (std::size_t i = 0; i < n; ++i)
    if (vr[i] != pf::kStartAtRestReference)
      return fail(in, "fmi2SetBoolean: no boolean variable has value reference %u", vr[i]);
  for (std::size_t i = 0; i < n; ++i) {
    const bool at_rest = value[i] != fmi2False;
    if (at_rest != in->start_at_rest) in->model.reset();  // outputs at t = 0 from the new start
    in->start_at_rest = at_rest;
  }
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, fmi2Integer value[]) {
  return no_variables(c, vr, value, n, kGetStates, "fmi2GetInteger", "integer");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, const fmi2Integer value[]) {
  return no_variables(c, vr, value, n, kSetStates, "fmi2SetInteger", "integer");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[],
                                              size_t n, fmi2String value[]) {
  return no_variables(c, vr, value, n, kGetStates, "fmi2GetString", "string");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[],
                                              size_t n, const fmi2String value[]) {
  return no_variables(c, vr, value, n, kSetStates, "fmi2SetString", "string");
}

// The capabilities modelDescription.xml does not claim.
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate*) {
  return unsupported(c, "fmi2GetFMUstate (canGetAndSetFMUstate = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate) {
  return unsupported(c, "fmi2SetFMUstate (canGetAndSetFMUstate = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate*) {
  return unsupported(c, "fmi2FreeFMUstate (canGetAndSetFMUstate = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate, size_t*) {
  return unsupported(c, "fmi2SerializedFMUstateSize (canSerializeFMUstate = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate, fmi2Byte[],
                                                      size_t) {
  return unsupported(c, "fmi2SerializeFMUstate (canSerializeFMUstate = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte[], size_t,
                                                        fmi2FMUstate*) {
  return unsupported(c, "fmi2DeSerializeFMUstate (canSerializeFMUstate = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c,
                                                             const fmi2ValueReference[], size_t,
                                                             const fmi2ValueReference[], size_t,
                                                             const fmi2Real[], fmi2Real[]) {
  return unsupported(c, "fmi2GetDirectionalDerivative (providesDirectionalDerivative = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c,
                                                            const fmi2ValueReference[], size_t,
                                                            const fmi2Integer[], const fmi2Real[]) {
  return unsupported(c, "fmi2SetRealInputDerivatives (canInterpolateInputs = false)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c,
                                                             const fmi2ValueReference[], size_t,
                                                             const fmi2Integer[], fmi2Real[]) {
  return unsupported(c, "fmi2GetRealOutputDerivatives (maxOutputDerivativeOrder = 0)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2CancelStep(fmi2Component c) {
  return unsupported(c, "fmi2CancelStep (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) {
  return unsupported(c, "fmi2GetStatus (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind,
                                                  fmi2Real*) {
  return unsupported(c, "fmi2GetRealStatus (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind,
                                                     fmi2Integer*) {
  return unsupported(c, "fmi2GetIntegerStatus (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind,
                                                     fmi2Boolean*) {
  return unsupported(c, "fmi2GetBooleanStatus (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind,
                                                    fmi2String*) {
  return unsupported(c, "fmi2GetStringStatus (steps are synchronous)");
}
