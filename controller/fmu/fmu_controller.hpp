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
// initial state (a start from rest), and set_previous_command() only counts the commands the
// actuator held instead of an answer (the FMU is not told). A call that returns fmi2Error or
// fmi2Fatal during the loop cannot throw there: the step returns the safe command (zero force)
// from then on (until a reset succeeds) and failure() names the call and the sample; check()
// throws it after the run. The calls keep to FMI 2.0's state machine: after fmi2Error only
// fmi2Reset or fmi2FreeInstance, after fmi2Fatal no call at all (not even at destruction).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/fmi2.h"
#include "numeric/channel_limits.hpp"

namespace flexloop::controller::fmu {

/// The first call in the loop that returned fmi2Error or fmi2Fatal (a string literal), the status
/// and the sample; call == nullptr while none has. Plain data: the step writes it.
struct FmuFailure {
  const char* call = nullptr;
  fmi2Status status = fmi2OK;
  long sample = 0;
};

struct FmuControllerSettings {
  std::string file;                  ///< the .fmu, as errors name it
  std::vector<std::string> inputs;   ///< the FMU's real inputs, in the sensors' order
  std::vector<std::string> outputs;  ///< the FMU's real outputs, in the actuators' order
  std::vector<std::pair<std::string, double>> parameters;  ///< real parameters set at start-up
  double period = 0;                                       ///< the loop's sample time [s]
  /// Optional: also told of a failure in the loop, for a caller that gives the controller away
  /// (a run consumes it) and asks afterwards. Must outlive the controller.
  FmuFailure* failure_sink = nullptr;
};

/// "fmi2DoStep returned fmi2Error at sample 12 (t = 0.0012 s)"; empty for no failure.
std::string describe(const FmuFailure& f, double period);

class FmuController {
 public:
  using Vector = numeric::BoundedVector<double, numeric::kMaxChannels>;

  /// @throws flexloop::InputError naming the FMU file and what is wrong (archive, description,
  /// version, Co-Simulation, variables, step size, library, or a call's fmi2Error/fmi2Fatal).
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
  /// as a failure in the loop (failure(), check()), with the safe command held from then on.
  void start(const Vector& y_now, const Vector& u_now) noexcept;
  /// fmi2Reset, then the parameters and initialisation again; failures as start().
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
