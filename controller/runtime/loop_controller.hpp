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
//
// step, start, reset and set_previous_command run in the real-time loop: the concept requires
// them noexcept (a controller that can fail, e.g. foreign code, reports it another way).
//
// The safe command, which the plant applies when answers stop coming, is zero force: the
// controller does not choose it (the plant holds it without a controller to ask).
#include <Eigen/Core>
#include <concepts>

namespace flexloop::controller::runtime {

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
};

}  // namespace flexloop::controller::runtime
