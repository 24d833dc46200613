// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A user's controller as an FMI 2.0 Co-Simulation FMU in the loop (issue 33), a LoopController
// (controller/runtime/loop_controller.hpp). Start-up (from_settings): unpack the archive into a
// private directory, read modelDescription.xml, find the mapped real inputs and outputs and the
// parameters, load the library, instantiate, set the parameters, set up the experiment, enter and
// exit initialisation. Each sample: fmi2SetReal the sensors, fmi2DoStep over one period from the
// sample's time, fmi2GetReal the commands; our side allocates nothing there (value references and
// buffers are sized at start-up). What the FMU's own code does in those calls is its own.
//
// An FMU cannot be set to a command or a state from outside: start() and reset() reset it to its
// initial state (a start from rest; an instance that is still as initialised at start-up is left
// as it is: no fmi2Reset and re-initialisation in the loop's first cycle), and
// set_previous_command() only counts the commands the actuator held instead of an answer (the FMU
// is not told). Statuses, as FMI 2.0 defines them: fmi2Warning is counted (the first call, sample
// and logged warning kept); fmi2Discard (the FMU could not complete the step; fmi2Terminated and
// fmi2LastSuccessfulTime are asked where the FMU offers them), fmi2Pending (an asynchronous step,
// which flexloop's synchronous loop cannot wait for), fmi2Error and fmi2Fatal end its run: it
// cannot throw in the loop, so the step returns the safe command (zero force) from then on (until
// a reset succeeds) and report() names the call, the status and the sample. The calls keep to
// FMI 2.0's state machine: after fmi2Discard or fmi2Error only fmi2Reset or fmi2FreeInstance, after
// fmi2Pending only fmi2FreeInstance, after fmi2Fatal no call at all (not even at destruction). The
// FMU's log callback writes into a ring (fmu_log_ring.hpp) that report() empties.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/fmi2.h"
#include "controller/fmu/fmu_archive.hpp"
#include "controller/runtime/loop_controller.hpp"
#include "numeric/channel_limits.hpp"

namespace flexloop::controller::fmu {

/// A status query after an fmi2Discard (fmi2GetBooleanStatus(fmi2Terminated),
/// fmi2GetRealStatus(fmi2LastSuccessfulTime)): not offered (the library does not export it),
/// its status, and the value it gave when that status was fmi2OK.
struct FmuStatusQuery {
  bool offered = false;
  fmi2Status status = fmi2OK;
  double value = 0;
};

/// The first call in the loop that ended the FMU's run (fmi2Discard, fmi2Error, fmi2Fatal,
/// fmi2Pending; a string literal), the status and the sample; call == nullptr while none has.
/// Plain data: the step writes it.
struct FmuFailure {
  const char* call = nullptr;
  fmi2Status status = fmi2OK;
  long sample = 0;
  FmuStatusQuery terminated, last_successful_time;  ///< asked after fmi2Discard only
};

struct FmuControllerSettings {
  std::string file;                  ///< the .fmu, as errors name it
  std::vector<std::string> inputs;   ///< the FMU's real inputs, in the sensors' order
  std::vector<std::string> outputs;  ///< the FMU's real outputs, in the actuators' order
  std::vector<std::pair<std::string, double>> parameters;  ///< real parameters set at start-up
  double period = 0;                                       ///< the loop's sample time [s]
  /// The SHA-256 the file must have (lower-case hex: the artefact's record of what it was built
  /// with); empty: not checked.
  std::string sha256;
  std::string artefact;             ///< the artefact that records sha256, as the refusal names it
  FmuArchiveLimits archive_limits;  ///< caps on unpacking (the scene's fmu_max_unpacked_mb)
};

/// "fmi2DoStep returned fmi2Discard at sample 12 (t = 0.0012 s); fmi2Terminated: true,
/// fmi2LastSuccessfulTime: 0.0011 s"; empty for no failure.
std::string describe(const FmuFailure& f, double period);

class FmuController {
 public:
  using Vector = numeric::BoundedVector<double, numeric::kMaxChannels>;

  /// @throws flexloop::InputError naming the FMU file and what is wrong (a SHA-256 other than
  /// the settings', archive, description, version, Co-Simulation, variables, step size, library,
  /// or a start-up call that did not return fmi2OK or fmi2Warning).
  static FmuController from_settings(const FmuControllerSettings& s);

  FmuController(FmuController&&) noexcept;
  FmuController& operator=(FmuController&&) noexcept;
  ~FmuController();

  Eigen::Index sensors() const noexcept { return n_in_; }
  Eigen::Index actuators() const noexcept { return u_.size(); }

  /// One sample: y = the sensors (any vector expression of sensors() entries).
  template <typename Y>
  const Vector& step(const Eigen::MatrixBase<Y>& y) noexcept {
    for (Eigen::Index i = 0; i < n_in_; ++i) y_[static_cast<std::size_t>(i)] = y.coeff(i);
    step_buffers();
    return u_;
  }

  /// Resets the FMU (a start from rest; see the header comment). A call that fails is recorded
  /// as a failure in the loop (failure(), report()), with the safe command held from then on.
  void start(const Vector& y_now, const Vector& u_now) noexcept;
  /// fmi2Reset, then the parameters and initialisation again (nothing for an instance that has
  /// not stepped since it was initialised: it is at rest already); failures as start().
  void reset() noexcept;
  /// Counted only: an FMU's memory of its last command cannot be set from outside.
  void set_previous_command(const Vector&) noexcept { ++held_commands_; }
  /// A drawn (stationary) start cannot be given to an FMU: loop starts leave it at rest
  /// (artefact: the closed loop's start is unavailable). @throws std::logic_error.
  void set_state(const Eigen::VectorXd&) const;
  void set_earlier_command(int, const Vector&) const;
  long held_commands() const noexcept { return held_commands_; }

  /// Empty while every call has returned fmi2OK or fmi2Warning; else the first failure (kept
  /// through a reset that recovers the FMU: the run's verdict reports it).
  std::string failure() const;
  /// @throws flexloop::InputError naming the FMU when a call in the loop failed.
  void check() const;
  /// The failure, the warnings and the log messages since the last report (the log ring is
  /// emptied). Not on the real-time thread.
  runtime::ControllerReport report();

 private:
  struct Session;
  explicit FmuController(std::unique_ptr<Session> s);
  void step_buffers() noexcept;

  std::unique_ptr<Session> session_;
  Eigen::Index n_in_ = 0;
  std::array<double, numeric::kMaxChannels> y_{};
  Vector u_;
  long held_commands_ = 0;
};

}  // namespace flexloop::controller::fmu
