// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The ping-pong baseline (rt/pingpong_baseline.hpp) over iceoryx (rt/iceoryx_transport.hpp):
// the same messages, clock, wait and receive modes, CPUs and accounting, only the carrier is
// iceoryx's shared memory instead of LCM's UDP multicast (url and receive_path are unused).
// Both sides run in child processes: the caller owns RouDi (rt/roudi_process.hpp) and must not
// register with it, since RouDi terminates the processes still registered when it stops. The
// ping side's figures come back through an anonymous shared page (no /dev/shm entry).
#include "rt/pingpong_baseline.hpp"
#include "rt/roudi_process.hpp"

namespace flexloop::rt {

/// Runs the baseline against the running `roudi`. std::invalid_argument for bad options;
/// RoudiError when RouDi ended during the run (its pid and how it ended; the figures are not
/// reported); std::runtime_error when a side fails or the pong never answers.
PingPongResult run_iceoryx_pingpong_baseline(const PingPongOptions& options, RoudiProcess& roudi);

}  // namespace flexloop::rt
