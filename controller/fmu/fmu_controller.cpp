#include "controller/fmu/fmu_controller.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "common/address_sanitizer.hpp"
#include "common/input_error.hpp"
#include "controller/fmu/fmu_archive.hpp"
#include "controller/fmu/fmu_description.hpp"
#include "controller/fmu/fmu_library.hpp"

#if defined(FLEXLOOP_ADDRESS_SANITIZER)
#include <sanitizer/lsan_interface.h>
#endif

namespace flexloop::controller::fmu {

namespace {

// The FMU's log messages go to stderr (start-up, or an FMU that logs in its step: its choice).
void log_message(fmi2ComponentEnvironment, fmi2String instance, fmi2Status status,
                 fmi2String category, fmi2String message, ...) {
  static const char* const kStatus[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
  char text[1024];
  va_list args;
  va_start(args, message);
  std::vsnprintf(text, sizeof text, message ? message : "", args);
  va_end(args);
  std::fprintf(stderr, "FMU %s (%s, %s): %s\n", instance ? instance : "?",
               static_cast<unsigned>(status) < 6 ? kStatus[status] : "?", category ? category : "",
               text);
}

const fmi2CallbackFunctions kCallbacks = {log_message, std::calloc, std::free, nullptr, nullptr};

bool failed(fmi2Status s) {
  return s == fmi2Error || s == fmi2Fatal;
}

std::string status_name(fmi2Status s) {
  return s == fmi2Fatal   ? "fmi2Fatal"
         : s == fmi2Error ? "fmi2Error"
                          : "status " + std::to_string(s);
}

}  // namespace

struct FmuController::Session {
  std::string file;
  FmuDirectory dir;
  FmuDescription description;
  FmuLibrary library;
  fmi2Component instance = nullptr;
  std::vector<fmi2ValueReference> in, out, parameter;
  std::vector<double> parameter_value;
  double period = 0;
  long steps = 0;
  FmuFailure failure;        // since the last (re)initialisation: the steps stop on it
  FmuFailure first_failure;  // of the whole session: what failure() reports
  bool initialised = false;  // fmi2ExitInitializationMode returned fine since the last reset
  bool fatal = false;        // an fmi2Fatal: FMI 2.0 allows no further call to the FMU
  FmuFailure* sink = nullptr;

  explicit Session(const FmuControllerSettings& s)
      : file(s.file),
        dir(s.file),
        description(read_fmu_description(dir.path(), s.file)),
        library(dir.path(), description.model_identifier, s.file),
        period(s.period),
        sink(s.failure_sink) {}
  // The calls FMI 2.0's state machine allows: none after fmi2Fatal (the instance is left as it
  // is); after fmi2Error, or before initialisation ended, fmi2FreeInstance only; else
  // fmi2Terminate first.
  ~Session() {
    if (!instance) return;
    if (fatal) {
#if defined(FLEXLOOP_ADDRESS_SANITIZER)
      // Left unfreed on purpose (the standard forbids fmi2FreeInstance now): not a leak to report.
      __lsan_ignore_object(instance);
#endif
      return;
    }
    if (initialised && !failure.call) library.calls().terminate(instance);
    library.calls().free_instance(instance);
  }

  // Records a failed call (the first of the session stays what failure() reports).
  void record(const FmuFailure& f) noexcept {
    failure = f;
    fatal = fatal || f.status == fmi2Fatal;
    if (!first_failure.call) first_failure = f;
    if (sink && !sink->call) *sink = f;
  }

  // Parameters, experiment, initialisation: after fmi2Instantiate and after fmi2Reset alike.
  // Returns the first call that failed ({} when none did); throws nothing, as reset() runs it in
  // the loop's start.
  FmuFailure initialise() noexcept {
    const Fmi2Calls& f = library.calls();
    steps = 0;
    failure = {};
    initialised = false;
    const auto first = [&](fmi2Status status, const char* call) {
      if (failed(status)) record({call, status, 0});
      return failed(status);
    };
    (!parameter.empty() &&
     first(f.set_real(instance, parameter.data(), parameter.size(), parameter_value.data()),
           "fmi2SetReal (parameters)")) ||
        first(f.setup_experiment(instance, fmi2False, 0.0, 0.0, fmi2False, 0.0),
              "fmi2SetupExperiment") ||
        first(f.enter_initialization_mode(instance), "fmi2EnterInitializationMode") ||
        first(f.exit_initialization_mode(instance), "fmi2ExitInitializationMode");
    initialised = !failure.call;
    return failure;
  }
};

FmuController FmuController::from_settings(const FmuControllerSettings& s) {
  if (s.inputs.empty() || s.outputs.empty() ||
      s.inputs.size() > static_cast<std::size_t>(numeric::kMaxChannels) ||
      s.outputs.size() > static_cast<std::size_t>(numeric::kMaxChannels))
    throw common::InputError(s.file, "an FMU controller needs 1 .. " +
                                         std::to_string(numeric::kMaxChannels) +
                                         " inputs and outputs");
  if (!(s.period > 0)) throw common::InputError(s.file, "the loop's period must be positive");
  auto session = std::make_unique<Session>(s);
  Session& x = *session;
  const FmuDescription& d = x.description;
  if (!d.variable_step && d.step_size && std::abs(*d.step_size - s.period) > 1e-9 * s.period) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "its fixed step is %.9g s (no canHandleVariableCommunicationStepSize) and the "
                  "loop's period is %.9g s",
                  *d.step_size, s.period);
    throw common::InputError(s.file, text);
  }
  for (const auto& name : s.inputs) x.in.push_back(d.real(name, "input", s.file).value_reference);
  for (const auto& name : s.outputs)
    x.out.push_back(d.real(name, "output", s.file).value_reference);
  for (const auto& [name, value] : s.parameters) {
    x.parameter.push_back(d.real(name, "parameter", s.file).value_reference);
    x.parameter_value.push_back(value);
  }
  const std::string resources = "file://" + (x.dir.path() / "resources").string();
  x.instance = x.library.calls().instantiate("flexloop", fmi2CoSimulation, d.guid.c_str(),
                                             resources.c_str(), &kCallbacks, fmi2False, fmi2False);
  if (!x.instance)
    throw common::InputError(s.file, "fmi2Instantiate failed (returned no instance)");
  if (const FmuFailure f = x.initialise(); f.call)
    throw common::InputError(s.file, std::string(f.call) + " returned " + status_name(f.status));
  FmuController c(std::move(session));
  c.n_in_ = static_cast<Eigen::Index>(s.inputs.size());
  c.u_ = Vector::Zero(static_cast<Eigen::Index>(s.outputs.size()));
  return c;
}

FmuController::FmuController(std::unique_ptr<Session> s) : session_(std::move(s)) {}
FmuController::FmuController(FmuController&&) noexcept = default;
FmuController& FmuController::operator=(FmuController&&) noexcept = default;
FmuController::~FmuController() = default;

void FmuController::step_buffers() noexcept {
  Session& x = *session_;
  if (x.failure.call) return;  // u_ holds the safe command
  const Fmi2Calls& f = x.library.calls();
  const auto fail = [&](fmi2Status status, const char* call) {
    if (!failed(status)) return false;
    x.record({call, status, x.steps});
    u_.setZero();
    return true;
  };
  // The sample's time from its index: no drift from summing periods.
  const double t = static_cast<double>(x.steps) * x.period;
  if (fail(f.set_real(x.instance, x.in.data(), x.in.size(), y_.data()), "fmi2SetReal")) return;
  if (fail(f.do_step(x.instance, t, x.period, fmi2True), "fmi2DoStep")) return;
  if (fail(f.get_real(x.instance, x.out.data(), x.out.size(), u_.data()), "fmi2GetReal")) return;
  ++x.steps;
}

void FmuController::start(const Vector&, const Vector&) noexcept {
  reset();
}

void FmuController::reset() noexcept {
  Session& x = *session_;
  u_.setZero();
  held_commands_ = 0;
  if (x.fatal) return;  // no call after fmi2Fatal: the safe command stays
  x.initialised = false;
  if (const fmi2Status status = x.library.calls().reset(x.instance); failed(status)) {
    x.record({"fmi2Reset", status, x.steps});
    return;
  }
  x.initialise();
}

std::string describe(const FmuFailure& f, double period) {
  if (!f.call) return {};
  char t[64];
  std::snprintf(t, sizeof t, " (t = %.9g s)", static_cast<double>(f.sample) * period);
  return std::string(f.call) + " returned " + status_name(f.status) + " at sample " +
         std::to_string(f.sample) + t;
}

std::string FmuController::failure() const {
  return describe(session_->first_failure, session_->period);
}

void FmuController::set_state(const Eigen::VectorXd&) const {
  throw std::logic_error("FmuController: an FMU's state cannot be set from outside");
}

void FmuController::set_earlier_command(int, const Vector&) const {
  throw std::logic_error("FmuController: an FMU's earlier commands cannot be set from outside");
}

void FmuController::check() const {
  const std::string what = failure();
  if (!what.empty()) throw common::InputError(session_->file, what);
}

}  // namespace flexloop::controller::fmu
