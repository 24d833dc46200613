// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How a loop waits for messages, whatever carries them (LCM, rt/lcm_transport.hpp; iceoryx,
// rt/iceoryx_transport.hpp): the receive modes and the one wait loop both carriers run.
#include <cstdint>

#include "rt/monotonic_time.hpp"

namespace flexloop::rt {

/// kBlocking sleeps until a message is ready; kPolling spins on zero-timeout looks (a full CPU);
/// kHybrid sleeps until a given time (shortly before the message is expected), spins after.
enum class ReceiveMode { kBlocking, kPolling, kHybrid };

/// Handles messages of `carrier` until `done()` holds (checked after each batch) or
/// CLOCK_MONOTONIC reaches deadline_ns; returns how many were handled. The carrier provides
/// handle_pending() (handle what is ready now, return how many) and poll_ready(timeout_ns)
/// (1: ready, 0: timed out, -1: error). noexcept when those are.
template <class Carrier, class Done>
int handle_until_deadline(Carrier& carrier, std::int64_t deadline_ns, ReceiveMode mode, Done&& done,
                          std::int64_t spin_from_ns) noexcept {
  int handled = carrier.handle_pending();
  while (!done()) {
    const std::int64_t now = monotonic_now_ns();
    if (now >= deadline_ns) break;
    const bool block =
        mode == ReceiveMode::kBlocking || (mode == ReceiveMode::kHybrid && now < spin_from_ns);
    if (block) {
      const std::int64_t until =
          mode == ReceiveMode::kHybrid && spin_from_ns < deadline_ns ? spin_from_ns : deadline_ns;
      if (carrier.poll_ready(until - now) <= 0) continue;
    }
    handled += carrier.handle_pending();
  }
  return handled;
}

}  // namespace flexloop::rt
