// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The one controller interface of the online side: what `flexloop sim`, the controller process
// and the tests ask of a runtime controller. The PI force feedback (compiled and general) and the
// state-space controller are its implementations; a new law implements the same members.
//
//   step(y)                  one sample: the sensors in, the command to hold until the next
//                            sample out; never allocates, locks, throws or makes a system call
//   start(y_now, u_now)      bumpless start: the next step(y_now) returns u_now (or the closest
//                            command the law can give, where it cannot give every one)
//   reset()                  the state of a controller that has never run (zero state, zero
//                            command held)
//   set_previous_command(u)  the actuator applied u instead of the last answer (a held or safe
//                            command): the next measurement contains u's force
//   sensors(), actuators()   the channel counts
//   report()                 after the run (not in the loop): how the controller's own calls went
//                            (ControllerReport; always empty for flexloop's own kernels, which
//                            cannot fail; a controller FMU's failed call, warnings and log)
//
// step, start, reset and set_previous_command run in the real-time loop: the concept requires
// them noexcept (a controller that can fail, e.g. foreign code, answers with the safe command from
// its failure on and says so in report()).
//
// The safe command, which the plant applies when answers stop coming, is the held command ramped
// to zero over --safe-ramp (online/loop/plant_station.hpp): the controller does not choose it
// (the plant holds it without a controller to ask).
#include <Eigen/Core>
#include <concepts>
#include <string>
#include <vector>

namespace flexloop::controller::runtime {

/// What a controller says of its run, asked after it (allocates; never in the loop).
struct ControllerReport {
  /// Empty while the controller answered every sample itself; else its first failure (e.g.
  /// "fmi2DoStep returned fmi2Discard at sample 12 (t = 0.0012 s)"): from there on it answered
  /// with the safe command.
  std::string failure;
  /// The failure was the controller refusing its input (an FMU's fmi2Error or fmi2Fatal: the
  /// user's code or its parameters, an input error); false for a run the controller could not
  /// complete (fmi2Discard, fmi2Pending).
  bool refused = false;
  /// Warnings of calls that still answered (an FMU's fmi2Warning): how many, and the first.
  long warnings = 0;
  std::string first_warning;
  /// The controller's own log messages, in order, and how many did not fit its buffer.
  std::vector<std::string> messages;
  long messages_lost = 0;
};

template <class C>
concept LoopController = requires(C c, const C cc, const typename C::Vector v) {
  typename C::Vector;
  { cc.sensors() } -> std::convertible_to<Eigen::Index>;
  { cc.actuators() } -> std::convertible_to<Eigen::Index>;
  { c.step(v) }
  noexcept;
  { c.start(v, v) }
  noexcept;
  { c.reset() }
  noexcept;
  { c.set_previous_command(v) }
  noexcept;
  { c.report() } -> std::same_as<ControllerReport>;
};

}  // namespace flexloop::controller::runtime
