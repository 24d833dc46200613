// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// hil's live status line: once a second, what the plant loop reports through its shared
// LoopStatus (online/loop/loop_status.hpp), rewritten in place on standard error:
//   hil 10 kHz: 4 / 10 s, 40000 cycles, 12 misses (0.030 %), round trip p99 41.2 us, safe 0
// and, with no controller process (the plant alone, or a controller of the user's own):
//   hil 10 kHz, no controller process: 4 / 10 s, 40000 cycles, 40000 unanswered, ...
// Quiet when asked or when standard error is not a terminal (logs and CI stay clean).
// Orchestration only (the parent process, not the loop).
#include <cstdint>
#include <string>

#include "online/loop/loop_status.hpp"

namespace flexloop::hil {

class StatusLine {
 public:
  /// controller_process: hil started one (its unanswered samples are misses).
  StatusLine(const loop::LoopStatus& status, double rate_hz, bool wanted, bool controller_process);
  /// Prints the newest figures when the loop published new ones since the last call.
  void tick();
  /// Ends the line (a newline when anything was printed).
  void finish();
  bool enabled() const { return enabled_; }

  /// The line for these figures (no carriage return), for tests.
  static std::string format(double rate_hz, std::int64_t cycles, std::int64_t periods_planned,
                            std::int64_t misses, std::int64_t safe, std::int64_t round_trip_p99_ns,
                            bool controller_process);

 private:
  const loop::LoopStatus& status_;
  double rate_hz_;
  bool enabled_;
  bool controller_process_;
  std::int64_t seen_ = 0;
  bool printed_ = false;
};

}  // namespace flexloop::hil
