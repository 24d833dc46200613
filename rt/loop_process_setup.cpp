// SPDX-License-Identifier: BSD-3-Clause
#include "rt/loop_process_setup.hpp"

namespace flexloop::rt {

LoopProcessSetup set_up_loop_process(LcmTransport& lcm, const RealtimeOptions& options) {
  const RealtimeReport report = apply_realtime_setup(options);
  LoopProcessSetup out{report.fifo, report.describe()};
  if (report.fifo)
    for (const SetupStatus& s :
         lcm.configure_receive_thread(options.cpu, options.fifo_priority + 1))
      out.text += (s.ok ? "  ok    LCM receive: " : "  WARN  LCM receive: ") + s.message + "\n";
  return out;
}

ReceiveMode receive_mode_for(WaitMode mode) noexcept {
  switch (mode) {
    case WaitMode::kHybrid:
      return ReceiveMode::kHybrid;
    case WaitMode::kSpin:
      return ReceiveMode::kPolling;
    case WaitMode::kSleep:
      break;
  }
  return ReceiveMode::kBlocking;
}

}  // namespace flexloop::rt
