// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant process's work in one period, without clocks or sockets (so that tests can drive it
// sample by sample): the simulated hardware of the scene (plant/runtime/simulated_hardware.hpp:
// the discrete plant with inputs [w (disturbances); u (actuator commands)] and outputs
// [z (performance); y (sensors)], compiled sizes or sized at start-up, the scene's floor, and
// whichever actuator, sensor and transport effects the scene asks for, composed as
// online/sim/loop_hardware.hpp composes them for `flexloop sim`).
//
// Cycle k (k = 0, 1, ...), as the real-time loop calls it:
//   settle(due_k)  decide the command u that is held over the last period and apply it
//                  (actuator, then the plant advances with [w_{k-1}; force]). u is
//                    the answer to sample k-1 when it was received by due_k     (answered)
//                    else the command held before (a deadline miss)             (held)
//                    else, once `safe_after` consecutive samples were missed, the safe
//                    command: a controlled stop that ramps the held answer linearly to zero
//                    over `safe_ramp_periods` (0: zero at once), then zero        (safe)
//                  An answer that came for an older sample, or after due_k, is late: counted,
//                  never applied. Nothing happens at k = 0 (no sample was out yet).
//   sample(t_k)    the hardware's sample k (floor w_k, plant outputs with the force held, the
//                  sensors' readings after their effects) into the sensor message (seq k + 1,
//                  t_ns = t_k, and what the actuators held: applied_scale x the answer to
//                  sample applied_seq -- scale 1 for an answer or a held one, 1 > scale > 0 on
//                  the safe ramp, applied_seq 0 and scale 0 for zero).
// With every answer in time this is exactly the in-process loop of online/sim/closed_loop_run.hpp
// (tests/hil/test_stations.cpp checks it bit for bit, with and without effects). When answers
// return after the safe command, the plant applies them at once; the controller makes that
// bumpless (online/loop/controller_station.hpp restarts from the command the sample says was
// held). Why a ramp and not zero at once: a force-feedback loop cancels most of its struts'
// stiffness force, and zero force returns all of it in one period -- a kick that repeated stalls
// pump up (doc/external_controller.md, "The safe command").
//
// Commands arrive through commands(), a MessageInbox with a fixed epoch (this plant run's) and a
// maximum transit age of one period: messages that fail to decode, carry NaN/Inf, answer another
// plant run, took longer than a period in transit, repeat or reorder are dropped and counted
// there, never applied. settle() and sample() are noexcept and allocation-free.
#include <Eigen/Core>
#include <cstdint>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <limits>

#include <algorithm>
#include <type_traits>
#include <utility>

#include "rt/message_inbox.hpp"

namespace flexloop::loop {

struct PlantStationSettings {
  int safe_after = 10;     ///< consecutive missed answers before the safe command, >= 1
  std::int64_t epoch = 1;  ///< this plant run's id (sensor_sample_t.plant_epoch)
  std::int64_t period_ns = 1'000'000;
  /// A command of this magnitude or more saturates the actuator (its force limit over its gain);
  /// infinity: no limit.
  double command_limit = std::numeric_limits<double>::infinity();
  /// Periods over which the safe command ramps the held answer to zero; 0: zero at once.
  std::int64_t safe_ramp_periods = 0;
};

/// Where the command applied over the last period came from.
enum class CommandSource { kNone, kAnswer, kHeld, kSafe };

template <class Hardware>
class PlantStation {
  static_assert(std::is_same_v<typename Hardware::Scalar, double>, "messages carry doubles");

 public:
  using Command = typename Hardware::Command;

  /// Set-up; safe_after < 1 is taken as 1. Commands must carry one value per actuator.
  PlantStation(Hardware hardware, const PlantStationSettings& s)
      : hw_(std::move(hardware)),
        settings_(s),
        commands_(rt::OrderGate(rt::EpochPolicy::kFixed, s.epoch, s.period_ns),
                  {static_cast<int>(hw_.actuators()), 0}),
        u_(Command::Zero(hw_.actuators())) {
    if (settings_.safe_after < 1) settings_.safe_after = 1;
    if (settings_.safe_ramp_periods < 0) settings_.safe_ramp_periods = 0;
    msg_.plant_epoch = s.epoch;
    msg_.n_sensors = static_cast<std::int16_t>(hw_.sensors());
    msg_.n_performance = static_cast<std::int16_t>(hw_.performance_outputs());
    msg_.sensors.assign(static_cast<std::size_t>(msg_.n_sensors), 0.0);
    msg_.performance.assign(static_cast<std::size_t>(msg_.n_performance), 0.0);
  }

  rt::MessageInbox<flexloop_msgs::actuator_command_t>& commands() noexcept { return commands_; }
  const rt::MessageInbox<flexloop_msgs::actuator_command_t>& commands() const noexcept {
    return commands_;
  }

  /// True when the answer to the newest sample is in the inbox (the loop's "stop waiting").
  bool answered() const noexcept {
    return commands_.has_fresh() && commands_.newest().answers_seq == msg_.seq;
  }

  /// Start-up: the command the actuators held before the first sample (a stationary start,
  /// online/sim/loop_start.hpp), held until the first answer like an answer. Samples say it as
  /// applied_seq 0 with applied_scale > 0; the controller process draws the same command.
  void start_command(const Command& u) noexcept {
    u_ = answer_ = u;
    applied_seq_ = 0;
    applied_scale_ = 1.0;
    start_held_ = true;
  }

  /// Settles the last period (see the header comment); returns where its command came from.
  /// The applied answer, if any, is last_answer().
  CommandSource settle(std::int64_t due_ns) noexcept {
    last_answer_ = nullptr;
    if (msg_.seq == 0) return CommandSource::kNone;
    const flexloop_msgs::actuator_command_t* a = commands_.take();
    CommandSource source = CommandSource::kAnswer;
    if (a != nullptr && a->answers_seq == msg_.seq && commands_.newest_received_ns() <= due_ns) {
      consecutive_misses_ = 0;
      last_answer_ = a;
      applied_seq_ = a->answers_seq;
      applied_scale_ = 1.0;
      answer_ = Eigen::Map<const Command>(a->commands.data(), u_.size());
      u_ = answer_;
    } else {
      if (a != nullptr) ++late_answers_;
      ++deadline_misses_;
      ++consecutive_misses_;
      source = CommandSource::kHeld;
      if (consecutive_misses_ >= settings_.safe_after) {
        source = CommandSource::kSafe;
        ramp_down(consecutive_misses_ - settings_.safe_after + 1);
        ++safe_command_cycles_;
      }
    }
    hw_.apply(u_);
    // What the run did physically: the true performance outputs of the sample this command
    // answered and the command held over the period, as the in-process loop sums them.
    sum_z2_ += hw_.performance().cwiseAbs2();
    sum_u2_ += u_.cwiseAbs2();
    if ((u_.cwiseAbs().array() >= settings_.command_limit).any()) ++saturated_cycles_;
    ++settled_;
    return source;
  }

  /// Takes sample k at t_ns: the message to publish.
  const flexloop_msgs::sensor_sample_t& sample(std::int64_t t_ns) noexcept {
    const auto& reading = hw_.sample();
    // Maps of the hardware's own vector types: their sizes are then known to the compiler too.
    Eigen::Map<typename Hardware::Performance>(msg_.performance.data(), msg_.n_performance) =
        reading.performance;
    Eigen::Map<typename Hardware::Sensors>(msg_.sensors.data(), msg_.n_sensors) = reading.sensors;
    msg_.seq += 1;
    msg_.t_ns = t_ns;
    msg_.applied_seq = applied_seq_;
    msg_.applied_scale = applied_scale_;
    return msg_;
  }

  /// The newest sample (seq 0 before the first).
  const flexloop_msgs::sensor_sample_t& last_sample() const noexcept { return msg_; }
  /// The answer applied by the last settle(), or nullptr.
  const flexloop_msgs::actuator_command_t* last_answer() const noexcept { return last_answer_; }
  /// The command the actuators hold now (what they make of it: hardware().actuator_force()).
  const Command& command() const noexcept { return u_; }
  const Hardware& hardware() const noexcept { return hw_; }

  /// RMS of each true performance output and each command over the settled periods (allocates:
  /// for the report after the run).
  Eigen::VectorXd rms_performance() const {
    return (sum_z2_.template cast<double>() /
            static_cast<double>(std::max<std::int64_t>(settled_, 1)))
        .cwiseSqrt();
  }
  Eigen::VectorXd rms_command() const {
    return (sum_u2_.template cast<double>() /
            static_cast<double>(std::max<std::int64_t>(settled_, 1)))
        .cwiseSqrt();
  }
  /// Share of the settled periods in which a command reached command_limit.
  double saturated_share() const noexcept {
    return settled_ > 0 ? static_cast<double>(saturated_cycles_) / static_cast<double>(settled_)
                        : 0.0;
  }
  std::int64_t samples() const noexcept { return msg_.seq; }
  std::int64_t deadline_misses() const noexcept { return deadline_misses_; }
  std::int64_t late_answers() const noexcept { return late_answers_; }
  std::int64_t safe_command_cycles() const noexcept { return safe_command_cycles_; }
  int consecutive_misses() const noexcept { return consecutive_misses_; }
  const PlantStationSettings& settings() const noexcept { return settings_; }

 private:
  // Safe period j (1, 2, ...): the held answer times 1 - j / safe_ramp_periods, zero from then on.
  // The controller computes the same product from the sample (bit for bit: one multiply).
  void ramp_down(std::int64_t j) noexcept {
    const auto n = settings_.safe_ramp_periods;
    const bool holding = applied_seq_ > 0 || start_held_;
    applied_scale_ = holding && j < n ? 1.0 - static_cast<double>(j) / static_cast<double>(n) : 0.0;
    if (applied_scale_ == 0.0) {
      applied_seq_ = 0;
      start_held_ = false;
      u_.setZero();
    } else {
      u_ = applied_scale_ * answer_;
    }
  }

  Hardware hw_;
  PlantStationSettings settings_;
  rt::MessageInbox<flexloop_msgs::actuator_command_t> commands_;
  Command u_;
  Command answer_ = Command::Zero(hw_.actuators());  // the last answer applied
  typename Hardware::Performance sum_z2_ = Hardware::Performance::Zero(hw_.performance_outputs());
  Command sum_u2_ = Command::Zero(hw_.actuators());
  std::int64_t saturated_cycles_ = 0, settled_ = 0;
  std::int64_t applied_seq_ = 0;  // the answer held now (its sample's seq); 0: the zero command
  bool start_held_ = false;       // applied_seq_ 0 with a scale > 0: the start's command
  double applied_scale_ = 0.0;    // u_ = applied_scale_ * that answer
  flexloop_msgs::sensor_sample_t msg_{};
  const flexloop_msgs::actuator_command_t* last_answer_ = nullptr;
  std::int64_t deadline_misses_ = 0;
  std::int64_t late_answers_ = 0;
  std::int64_t safe_command_cycles_ = 0;
  int consecutive_misses_ = 0;
};

}  // namespace flexloop::loop
