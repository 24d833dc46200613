// The FMI 2.0 Co-Simulation functions of the plant FMU that `flexloop export-fmu` writes
// (issue 33). The one library serves every exported machine: fmi2Instantiate reads the loop
// artefact from the FMU's resources/ (written beside the GUID it was exported with), and the
// variables are plant_fmu_variables.hpp's. One fmi2DoStep(t, h) is one loop period h = 1 / rate:
// the command set before it is held over [t, t + h), the plant advances, and the outputs are the
// sample at t + h -- the convention of `flexloop sim` (online/sim/closed_loop_run.hpp), so that a
// master that reads the outputs, computes its command, sets it and steps runs sim's loop.
// No exception leaves this file: each becomes a logged fmi2Error.
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/fmi2.h"
#include "online/plant_fmu/plant_fmu_model.hpp"
#include "online/plant_fmu/plant_fmu_variables.hpp"

namespace {

namespace pf = flexloop::plant_fmu;

enum class Phase { kInstantiated, kInitialising, kStepping, kTerminated };

struct PlantInstance {
  std::string name;
  const fmi2CallbackFunctions* callbacks = nullptr;
  flexloop::artefact::LoopArtefact loop;
  std::unique_ptr<pf::PlantFmuModel> model;
  std::size_t inputs = 0;
  std::vector<double> values;  // by value reference: the commands, then the readings
  bool start_at_rest = false;
  Phase phase = Phase::kInstantiated;
};

void log(const PlantInstance* in, fmi2Status status, const std::string& message) {
  if (in && in->callbacks && in->callbacks->logger)
    in->callbacks->logger(in->callbacks->componentEnvironment, in->name.c_str(), status,
                          status == fmi2OK ? "logAll" : "logStatusError", "%s", message.c_str());
}

fmi2Status error(const PlantInstance* in, const std::string& message) {
  log(in, fmi2Error, message);
  return fmi2Error;
}

PlantInstance* instance(fmi2Component c) {
  return static_cast<PlantInstance*>(c);
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

// The call that reads or writes variables: each reference in range, for its causality.
template <class F>
fmi2Status each_reference(PlantInstance* in, const fmi2ValueReference vr[], std::size_t n,
                          bool writing, const char* call, F&& f) {
  if (!in) return fmi2Error;
  if (n > 0 && !vr) return error(in, std::string(call) + ": no value references");
  for (std::size_t i = 0; i < n; ++i) {
    if (vr[i] >= in->values.size())
      return error(in, std::string(call) + ": no real variable has value reference " +
                           std::to_string(vr[i]));
    if (writing && vr[i] >= in->inputs)
      return error(in, std::string(call) + ": value reference " + std::to_string(vr[i]) +
                           " is an output (only the actuators' commands are inputs)");
    f(i, vr[i]);
  }
  return fmi2OK;
}

fmi2Status unsupported(fmi2Component c, const char* call) {
  return error(instance(c), std::string(call) + " is not supported by this FMU");
}

}  // namespace

#define FLEXLOOP_FMI2_EXPORT extern "C" __attribute__((visibility("default")))

FLEXLOOP_FMI2_EXPORT const char* fmi2GetTypesPlatform() {
  return "default";
}
FLEXLOOP_FMI2_EXPORT const char* fmi2GetVersion() {
  return "2.0";
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean, size_t,
                                                    const fmi2String[]) {
  return c ? fmi2OK : fmi2Error;
}

FLEXLOOP_FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                                   fmi2String resources,
                                                   const fmi2CallbackFunctions* callbacks,
                                                   fmi2Boolean, fmi2Boolean) {
  auto in = std::make_unique<PlantInstance>();
  in->name = name ? name : "flexloop_plant";
  in->callbacks = callbacks;
  try {
    if (type != fmi2CoSimulation)
      throw std::runtime_error("this FMU is for Co-Simulation only (no Model Exchange)");
    const std::filesystem::path dir = resource_directory(resources);
    const std::string exported = read_text(dir / pf::kGuidResource);
    if (!guid || exported != guid)
      throw std::runtime_error("GUID " + std::string(guid ? guid : "(none)") +
                               " is not this FMU's " + exported);
    in->loop = flexloop::artefact::read_loop_artefact(dir / pf::kArtefactResource);
    in->inputs = static_cast<std::size_t>(in->loop.actuators());
    in->values.assign(pf::plant_fmu_variables(in->loop).size(), 0.0);
  } catch (const std::exception& e) {
    log(in.get(), fmi2Error, std::string("fmi2Instantiate: ") + e.what());
    return nullptr;
  }
  return in.release();
}

FLEXLOOP_FMI2_EXPORT void fmi2FreeInstance(fmi2Component c) {
  delete instance(c);
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real,
                                                    fmi2Real start, fmi2Boolean, fmi2Real) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (start != 0)
    return error(in,
                 "fmi2SetupExperiment: the plant starts at t = 0 (its floor and noise are "
                 "seeded sequences), not at " +
                     std::to_string(start));
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in || in->phase != Phase::kInstantiated)
    return error(in,
                 "fmi2EnterInitializationMode: "
                 "not after fmi2Instantiate");
  in->phase = Phase::kInitialising;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in || in->phase != Phase::kInitialising)
    return error(in, "fmi2ExitInitializationMode: not in initialisation mode");
  try {
    in->model = pf::PlantFmuModel::from_artefact(in->loop, in->start_at_rest);
  } catch (const std::exception& e) {
    return error(in, std::string("fmi2ExitInitializationMode: ") + e.what());
  }
  in->model->sample(in->values.data() + in->inputs);  // the outputs at t = 0
  in->phase = Phase::kStepping;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real, fmi2Real h, fmi2Boolean) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  if (in->phase != Phase::kStepping) return error(in, "fmi2DoStep: not initialised");
  const double dt = in->loop.dt();
  if (!(std::abs(h - dt) <= 1e-9 * dt))
    return error(in, "fmi2DoStep: the step is " + std::to_string(h) +
                         " s; this plant is discrete at its loop period " + std::to_string(dt) +
                         " s (its DefaultExperiment stepSize)");
  in->model->apply(in->values.data());
  in->model->sample(in->values.data() + in->inputs);
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  in->phase = Phase::kTerminated;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component c) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  in->model.reset();
  std::fill(in->values.begin(), in->values.end(), 0.0);
  in->start_at_rest = false;
  in->phase = Phase::kInstantiated;
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[],
                                            size_t n, fmi2Real value[]) {
  PlantInstance* in = instance(c);
  return each_reference(in, vr, n, false, "fmi2GetReal",
                        [&](std::size_t i, unsigned r) { value[i] = in->values[r]; });
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[],
                                            size_t n, const fmi2Real value[]) {
  PlantInstance* in = instance(c);
  for (std::size_t i = 0; in && i < n; ++i)
    if (!std::isfinite(value[i]))
      return error(in, "fmi2SetReal: the command for value reference " + std::to_string(vr[i]) +
                           " is not finite");
  return each_reference(in, vr, n, true, "fmi2SetReal",
                        [&](std::size_t i, unsigned r) { in->values[r] = value[i]; });
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, fmi2Boolean value[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  for (std::size_t i = 0; i < n; ++i) {
    if (vr[i] != pf::kStartAtRestReference)
      return error(
          in, "fmi2GetBoolean: no boolean variable has value reference " + std::to_string(vr[i]));
    value[i] = in->start_at_rest ? fmi2True : fmi2False;
  }
  return fmi2OK;
}

FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, const fmi2Boolean value[]) {
  PlantInstance* in = instance(c);
  if (!in) return fmi2Error;
  for (std::size_t i = 0; i < n; ++i) {
    if (vr[i] != pf::kStartAtRestReference)
      return error(
          in, "fmi2SetBoolean: no boolean variable has value reference " + std::to_string(vr[i]));
    if (in->phase == Phase::kStepping)
      return error(in, "fmi2SetBoolean: start_at_rest is fixed once initialised");
    in->start_at_rest = value[i] != fmi2False;
  }
  return fmi2OK;
}

// No integer or string variables: only an empty request succeeds.
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference[],
                                               size_t n, fmi2Integer[]) {
  return n == 0 ? fmi2OK : unsupported(c, "fmi2GetInteger (no integer variables)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference[],
                                               size_t n, const fmi2Integer[]) {
  return n == 0 ? fmi2OK : unsupported(c, "fmi2SetInteger (no integer variables)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference[], size_t n,
                                              fmi2String[]) {
  return n == 0 ? fmi2OK : unsupported(c, "fmi2GetString (no string variables)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference[], size_t n,
                                              const fmi2String[]) {
  return n == 0 ? fmi2OK : unsupported(c, "fmi2SetString (no string variables)");
}

// The capabilities modelDescription.xml does not claim.
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate*) {
  return unsupported(c, "fmi2GetFMUstate");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate) {
  return unsupported(c, "fmi2SetFMUstate");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate*) {
  return unsupported(c, "fmi2FreeFMUstate");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate, size_t*) {
  return unsupported(c, "fmi2SerializedFMUstateSize");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate, fmi2Byte[],
                                                      size_t) {
  return unsupported(c, "fmi2SerializeFMUstate");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte[], size_t,
                                                        fmi2FMUstate*) {
  return unsupported(c, "fmi2DeSerializeFMUstate");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c,
                                                             const fmi2ValueReference[], size_t,
                                                             const fmi2ValueReference[], size_t,
                                                             const fmi2Real[], fmi2Real[]) {
  return unsupported(c, "fmi2GetDirectionalDerivative");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c,
                                                            const fmi2ValueReference[], size_t,
                                                            const fmi2Integer[], const fmi2Real[]) {
  return unsupported(c, "fmi2SetRealInputDerivatives");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c,
                                                             const fmi2ValueReference[], size_t,
                                                             const fmi2Integer[], fmi2Real[]) {
  return unsupported(c, "fmi2GetRealOutputDerivatives");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2CancelStep(fmi2Component c) {
  return unsupported(c, "fmi2CancelStep (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) {
  return unsupported(c, "fmi2GetStatus (steps are synchronous)");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind,
                                                  fmi2Real*) {
  return unsupported(c, "fmi2GetRealStatus");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind,
                                                     fmi2Integer*) {
  return unsupported(c, "fmi2GetIntegerStatus");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind,
                                                     fmi2Boolean*) {
  return unsupported(c, "fmi2GetBooleanStatus");
}
FLEXLOOP_FMI2_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind,
                                                    fmi2String*) {
  return unsupported(c, "fmi2GetStringStatus");
}
