// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The set-up every loop process does once LCM is open (doc/design.md §11 order): pin, lock memory
// and prefault the stack, then SCHED_FIFO when permitted (rt/realtime_setup.hpp); and, when
// SCHED_FIFO was granted, LCM's receive thread on the same CPU one priority level above the loop,
// so a polling loop cannot starve it. Used by the ping-pong baseline and the plant and controller
// processes alike, so that a loop and its baseline are set up the same way. Set-up only: may
// allocate; never throws for a refused privilege (the text says what was done or why not).
#include <string>

#include "rt/lcm_transport.hpp"
#include "rt/periodic_clock.hpp"
#include "rt/realtime_setup.hpp"

namespace flexloop::rt {

struct LoopProcessSetup {
  bool fifo = false;  ///< SCHED_FIFO asked for and granted
  std::string text;   ///< one line per step
};

/// Applies `options` to the calling thread and configures LCM's receive thread.
LoopProcessSetup set_up_loop_process(LcmTransport& lcm, const RealtimeOptions& options);

/// How a loop that waits in `mode` waits for messages: sleep -> block, hybrid -> hybrid,
/// spin -> poll.
ReceiveMode receive_mode_for(WaitMode mode) noexcept;

}  // namespace flexloop::rt
