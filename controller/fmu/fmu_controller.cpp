// SPDX-License-Identifier: BSD-3-Clause
#include "controller/fmu/fmu_controller.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "common/address_sanitizer.hpp"
#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "controller/fmu/fmu_archive.hpp"
#include "controller/fmu/fmu_description.hpp"
#include "controller/fmu/fmu_library.hpp"
#include "controller/fmu/fmu_log_ring.hpp"

#if defined(FLEXLOOP_ADDRESS_SANITIZER)
#include <sanitizer/lsan_interface.h>
#endif

namespace flexloop::controller::fmu {

namespace {

// The statuses that end the FMU's run (FMI 2.0 section 2.1.3): fmi2Warning still answered.
bool failed(fmi2Status s) {
  return s == fmi2Discard || s == fmi2Error || s == fmi2Fatal || s == fmi2Pending;
}

std::string status_name(fmi2Status s) {
  static const char* const kNames[] = {"fmi2OK",    "fmi2Warning", "fmi2Discard",
                                       "fmi2Error", "fmi2Fatal",   "fmi2Pending"};
  return static_cast<unsigned>(s) < 6 ? kNames[s] : "status " + std::to_string(s);
}

// The refusal of an FMU that is not the one the artefact was built with.
void require_built_file(const FmuControllerSettings& s) {
  if (s.sha256.empty()) return;
  const std::string now = common::file_sha256(s.file);
  if (now == s.sha256) return;
  throw common::InputError(
      s.file, "its SHA-256 is " + now + ", but " +
                  (s.artefact.empty() ? std::string("the artefact") : s.artefact) +
                  " was built with the file whose SHA-256 is " + s.sha256 +
                  ": the FMU changed after `flexloop build`; run `flexloop build` again on the "
                  "scene to run this FMU (or restore the FMU that was built)");
}

}  // namespace

struct FmuController::Session {
  std::string file;
  FmuDirectory dir;
  FmuDescription description;
  FmuLibrary library;
  FmuLogRing log;
  // The FMU keeps a pointer to these for the instance's life (the Session does not move).
  const fmi2CallbackFunctions callbacks;
  fmi2Component instance = nullptr;
  std::vector<fmi2ValueReference> in, out, parameter;
  std::vector<double> parameter_value;
  double period = 0;
  long steps = 0;
  FmuFailure failure;        // since the last (re)initialisation: the steps stop on it
  FmuFailure first_failure;  // of the whole session: what failure() reports
  bool initialised = false;  // fmi2ExitInitializationMode returned fine since the last reset
  bool fatal = false;        // an fmi2Fatal: FMI 2.0 allows no further call to the FMU
  bool pending = false;      // an fmi2Pending: only fmi2FreeInstance is left (no fmi2Reset)
  long warnings = 0;         // calls that returned fmi2Warning
  const char* first_warning_call = nullptr;
  long first_warning_sample = 0;

  explicit Session(const FmuControllerSettings& s)
      : file(s.file),
        dir(s.file, s.archive_limits),
        description(read_fmu_description(dir.path(), s.file)),
        library(dir.path(), description, s.file),
        log(s.file),
        callbacks{FmuLogRing::logger, std::calloc, std::free, nullptr, &log},
        period(s.period) {}
  // The calls FMI 2.0's state machine allows: none after fmi2Fatal (the instance is left as it
  // is); after a failed call, or before initialisation ended, fmi2FreeInstance only; else
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

  // A call's status: a warning counted, a failure recorded (false), else true.
  bool answered(fmi2Status status, const char* call) noexcept {
    if (status == fmi2Warning && warnings++ == 0) {
      first_warning_call = call;
      first_warning_sample = steps;
    }
    if (!failed(status)) return true;
    FmuFailure f{call, status, steps, {}, {}};
    if (status == fmi2Discard) ask_after_discard(f);
    record(f);
    return false;
  }

  // fmi2Terminated and fmi2LastSuccessfulTime, which FMI 2.0 allows after fmi2Discard.
  void ask_after_discard(FmuFailure& f) noexcept {
    const Fmi2Calls& c = library.calls();
    if (c.get_boolean_status) {
      fmi2Boolean terminated = fmi2False;
      f.terminated = {true, c.get_boolean_status(instance, fmi2Terminated, &terminated),
                      terminated ? 1.0 : 0.0};
    }
    if (c.get_real_status) {
      fmi2Real t = 0;
      f.last_successful_time = {true, c.get_real_status(instance, fmi2LastSuccessfulTime, &t), t};
    }
  }

  // Records a failed call (the first of the session stays what failure() reports).
  void record(const FmuFailure& f) noexcept {
    failure = f;
    fatal = fatal || f.status == fmi2Fatal;
    pending = pending || f.status == fmi2Pending;
    if (!first_failure.call) first_failure = f;
  }

  // Parameters, experiment, initialisation: after fmi2Instantiate and after fmi2Reset alike.
  // Returns the first call that failed ({} when none did); throws nothing, as reset() runs it in
  // the loop's start.
  FmuFailure initialise() noexcept {
    const Fmi2Calls& f = library.calls();
    steps = 0;
    failure = {};
    initialised = false;
    (parameter.empty() ||
     answered(f.set_real(instance, parameter.data(), parameter.size(), parameter_value.data()),
              "fmi2SetReal (parameters)")) &&
        answered(f.setup_experiment(instance, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                 "fmi2SetupExperiment") &&
        answered(f.enter_initialization_mode(instance), "fmi2EnterInitializationMode") &&
        answered(f.exit_initialization_mode(instance), "fmi2ExitInitializationMode");
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
  require_built_file(s);
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
                                             resources.c_str(), &x.callbacks, fmi2False, fmi2False);
  // What the FMU logged at start-up goes out now (start-up is not real-time).
  for (const std::string& m : x.log.take()) std::fprintf(stderr, "%s\n", m.c_str());
  if (!x.instance)
    throw common::InputError(s.file, "fmi2Instantiate failed (returned no instance)");
  const FmuFailure f = x.initialise();
  for (const std::string& m : x.log.take()) std::fprintf(stderr, "%s\n", m.c_str());
  if (f.call)
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
  // The sample's time from its index: no drift from summing periods.
  const double t = static_cast<double>(x.steps) * x.period;
  if (x.answered(f.set_real(x.instance, x.in.data(), x.in.size(), y_.data()), "fmi2SetReal") &&
      x.answered(f.do_step(x.instance, t, x.period, fmi2True), "fmi2DoStep") &&
      x.answered(f.get_real(x.instance, x.out.data(), x.out.size(), u_.data()), "fmi2GetReal")) {
    ++x.steps;
    return;
  }
  u_.setZero();
}

void FmuController::start(const Vector&, const Vector&) noexcept {
  reset();
}

void FmuController::reset() noexcept {
  Session& x = *session_;
  u_.setZero();
  held_commands_ = 0;
  // Still as initialised (no step since): at rest already; an fmi2Reset and a second
  // initialisation would only cost the loop's first cycle their time.
  if (x.initialised && x.steps == 0 && !x.failure.call) return;
  if (x.fatal || x.pending) return;  // no fmi2Reset allowed now: the safe command stays
  x.initialised = false;
  if (const fmi2Status status = x.library.calls().reset(x.instance); failed(status)) {
    x.record({"fmi2Reset", status, x.steps, {}, {}});
    return;
  }
  x.initialise();
}

namespace {

// "fmi2Terminated: true" / "fmi2Terminated: not asked (...)" / "... returned fmi2Error".
std::string describe_query(const char* kind, const FmuStatusQuery& q, bool real) {
  const std::string what =
      std::string(real ? "fmi2GetRealStatus(" : "fmi2GetBooleanStatus(") + kind + ")";
  if (!q.offered) return what + " not exported by the FMU";
  if (q.status != fmi2OK) return what + " returned " + status_name(q.status) + " (no answer)";
  char text[64];
  if (real)
    std::snprintf(text, sizeof text, ": %.9g s", q.value);
  else
    std::snprintf(text, sizeof text, ": %s", q.value != 0 ? "true" : "false");
  return std::string(kind) + text;
}

}  // namespace

std::string describe(const FmuFailure& f, double period) {
  if (!f.call) return {};
  char t[64];
  std::snprintf(t, sizeof t, " (t = %.9g s)", static_cast<double>(f.sample) * period);
  std::string text = std::string(f.call) + " returned " + status_name(f.status) + " at sample " +
                     std::to_string(f.sample) + t;
  if (f.status == fmi2Discard)
    text += "; " + describe_query("fmi2Terminated", f.terminated, false) + ", " +
            describe_query("fmi2LastSuccessfulTime", f.last_successful_time, true);
  if (f.status == fmi2Pending)
    text += " (an asynchronous step: flexloop steps an FMU synchronously and does not wait)";
  return text;
}

std::string FmuController::failure() const {
  return describe(session_->first_failure, session_->period);
}

runtime::ControllerReport FmuController::report() {
  Session& x = *session_;
  runtime::ControllerReport r;
  r.failure = failure();
  r.refused = x.first_failure.status == fmi2Error || x.first_failure.status == fmi2Fatal;
  r.warnings = x.warnings;
  if (x.warnings > 0) {
    r.first_warning = std::string(x.first_warning_call) + " returned fmi2Warning at sample " +
                      std::to_string(x.first_warning_sample);
    if (const std::string m = x.log.first_warning(); !m.empty()) r.first_warning += ": " + m;
  }
  r.messages = x.log.take();
  r.messages_lost = x.log.lost();
  return r;
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
