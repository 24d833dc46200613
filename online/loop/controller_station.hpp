// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The controller process's work for one sensor message, without sockets (so that tests can drive
// it message by message): the controller's step on the sample's sensor channels (any
// controller/runtime/loop_controller.hpp: the PI, compiled or general, or the state-space
// controller; loop_controller.hpp picks it), and the actuator message that answers the sample.
//
// Resynchronisation, decided from the sample's (plant_epoch, seq) alone:
//   - first sample, or a new plant_epoch (the plant restarted, its state and held command are
//     zero again): reset() -- the controller starts afresh, exactly as the in-process loop does
//     (a controller still as it was built is at rest already: a controller FMU then makes no
//     call, so the first real-time cycle is an ordinary step);
//   - a gap of `safe_after` or more unanswered samples within one epoch (this controller stopped
//     or stalled and the plant has applied its safe command meanwhile, a ramp of the held answer
//     to zero): bumpless start(y, applied) -- the first answer is exactly the command the plant
//     holds, and the controller's state continues from one that produces it (no jump when
//     answers return).
// What the plant applied: each sample says what the actuators held over the period before it:
// applied_scale x the answer to sample applied_seq (0: zero). When that is not this station's
// last answer as sent (it came late or was lost and the plant held an older one, or the safe
// ramp scaled it), the controller is told (set_previous_command) before it steps, so that it
// removes from the measurement the force that is in it, not its own last answer's. An answer
// the station no longer remembers (a new process in a running epoch) is taken as zero.
// Samples reach answer() through samples(), a MessageInbox that follows the plant's epoch:
// messages that fail to decode, carry NaN/Inf, belong to an older plant run, repeat or reorder
// are dropped and counted there, never answered. answer() is noexcept and allocation-free.
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <utility>
#include <vector>

#include "controller/runtime/loop_controller.hpp"
#include "online/sim/loop_start.hpp"
#include "rt/message_inbox.hpp"

namespace flexloop::loop {

template <controller::runtime::LoopController Controller>
class ControllerStation {
 public:
  using Vector = typename Controller::Vector;

  /// safe_after: the plant's --safe-after (< 1 is taken as 1). Samples must carry the
  /// controller's sensor count; answers carry its actuator count.
  /// The controller's state and last command at the plant's start (online/sim/loop_start.hpp):
  /// each new epoch starts there. Empty: at rest (reset()).
  using Start = sim::DrawnStart;

  ControllerStation(Controller controller, int safe_after, Start start = {})
      : controller_(std::move(controller)),
        start_(std::move(start)),
        safe_after_(safe_after < 1 ? 1 : safe_after),
        samples_(rt::OrderGate{}, {static_cast<int>(controller_.sensors()), 0}),
        sent_(kRemembered, Vector::Zero(controller_.actuators())),
        sent_seq_(kRemembered, -1),
        held_(Vector::Zero(controller_.actuators())),
        applied_(Vector::Zero(controller_.actuators())) {
    cmd_.n_commands = static_cast<std::int16_t>(controller_.actuators());
    cmd_.commands.assign(static_cast<std::size_t>(cmd_.n_commands), 0.0);
  }

  rt::MessageInbox<flexloop_msgs::sensor_sample_t>& samples() noexcept { return samples_; }
  const rt::MessageInbox<flexloop_msgs::sensor_sample_t>& samples() const noexcept {
    return samples_;
  }

  /// The answer to `s` (t_ns and controller_compute_ns are left to the caller, who times it).
  flexloop_msgs::actuator_command_t& answer(const flexloop_msgs::sensor_sample_t& s) noexcept {
    const Eigen::Map<const Vector> y(s.sensors.data(), s.n_sensors);
    if (!started_ || s.plant_epoch != epoch_) {
      if (started_) ++resyncs_;
      controller_.reset();
      if (start_.last_command.size() > 0) sim::start_controller_at(start_, controller_);
      std::fill(sent_seq_.begin(), sent_seq_.end(), -1);
      held_seq_ = -1;
      epoch_ = s.plant_epoch;
      started_ = true;
    } else if (s.seq - last_seq_ > safe_after_) {
      controller_.start(y, applied(s));
      ++resumes_;
    } else if (s.applied_seq != last_seq_ || s.applied_scale != 1.0) {
      ++followed_;
      controller_.set_previous_command(applied(s));
    } else {
      remember_held(s.applied_seq);  // the plant holds this station's last answer
    }
    last_seq_ = s.seq;
    // Maps of the controller's own vector type: its size is then known to the compiler too.
    const auto& u = controller_.step(y);
    Eigen::Map<Vector>(cmd_.commands.data(), cmd_.n_commands) = u;
    const auto slot = static_cast<std::size_t>(s.seq % kRemembered);
    sent_[slot] = u;
    sent_seq_[slot] = s.seq;
    cmd_.seq += 1;
    cmd_.answers_seq = s.seq;
    cmd_.plant_epoch = s.plant_epoch;
    return cmd_;
  }

  const Controller& controller() const noexcept { return controller_; }
  /// What the controller says of its run (loop_controller.hpp): after the run, not in it.
  controller::runtime::ControllerReport report() { return controller_.report(); }
  std::int64_t answered() const noexcept { return cmd_.seq; }
  /// Plant restarts followed.
  std::int64_t resyncs() const noexcept { return resyncs_; }
  /// Bumpless restarts after a gap of safe_after or more samples.
  std::int64_t resumes() const noexcept { return resumes_; }
  /// Samples whose held command was not this station's last answer (followed before the step).
  std::int64_t followed() const noexcept { return followed_; }

 private:
  // The answers sent for the last kRemembered samples, by seq; and the one the plant holds, which
  // it may go on holding longer than that (a large safe_after).
  static constexpr std::int64_t kRemembered = 64;

  void remember_held(std::int64_t applied) noexcept {
    const auto slot = static_cast<std::size_t>(applied % kRemembered);
    if (applied <= 0 || sent_seq_[slot] != applied) return;
    held_ = sent_[slot];
    held_seq_ = applied;
  }

  // What the plant held over the period before `s`: applied_scale x the answer to applied_seq
  // (the same single multiply as the plant's, so bit for bit); zero when it is not remembered.
  const Vector& applied(const flexloop_msgs::sensor_sample_t& s) noexcept {
    remember_held(s.applied_seq);
    if (s.applied_seq == 0 && s.applied_scale > 0 && start_.last_command.size() > 0)
      applied_ = s.applied_scale * Vector(start_.last_command);  // the start's command
    else if (s.applied_seq <= 0 || s.applied_seq != held_seq_)
      applied_.setZero();
    else
      applied_ = s.applied_scale * held_;
    return applied_;
  }

  Controller controller_;
  Start start_;
  std::int64_t safe_after_;
  rt::MessageInbox<flexloop_msgs::sensor_sample_t> samples_;
  flexloop_msgs::actuator_command_t cmd_{};
  bool started_ = false;
  std::int64_t epoch_ = 0;
  std::int64_t last_seq_ = 0;
  std::int64_t resyncs_ = 0;
  std::int64_t resumes_ = 0;
  std::int64_t followed_ = 0;
  std::vector<Vector> sent_;
  std::vector<std::int64_t> sent_seq_;
  Vector held_;
  std::int64_t held_seq_ = -1;
  Vector applied_;
};

}  // namespace flexloop::loop
