// SPDX-License-Identifier: BSD-3-Clause
#include "online/hil/status_line.hpp"

#include <unistd.h>

#include <cstdio>

namespace flexloop::hil {

StatusLine::StatusLine(const loop::LoopStatus& status, double rate_hz, bool wanted,
                       bool controller_process)
    : status_(status),
      rate_hz_(rate_hz),
      enabled_(wanted && isatty(STDERR_FILENO) == 1),
      controller_process_(controller_process) {}

std::string StatusLine::format(double rate_hz, std::int64_t cycles, std::int64_t periods_planned,
                               std::int64_t misses, std::int64_t safe,
                               std::int64_t round_trip_p99_ns, bool controller_process) {
  char line[200];
  const double share =
      cycles > 0 ? 100.0 * static_cast<double>(misses) / static_cast<double>(cycles) : 0.0;
  // Without a controller process a sample without an answer is what is expected (the plant
  // alone, or a process of the user's that may answer some): counted, not called a miss.
  char answers[64];
  if (controller_process)
    std::snprintf(answers, sizeof answers, "%lld misses (%.3f %%)", static_cast<long long>(misses),
                  share);
  else
    std::snprintf(answers, sizeof answers, "%lld unanswered", static_cast<long long>(misses));
  std::snprintf(line, sizeof line,
                "hil %.6g kHz%s: %.0f / %.0f s, %lld cycles, %s, round trip p99 %.1f us, safe %lld",
                rate_hz / 1e3, controller_process ? "" : ", no controller process",
                static_cast<double>(cycles) / rate_hz,
                static_cast<double>(periods_planned) / rate_hz, static_cast<long long>(cycles),
                answers, static_cast<double>(round_trip_p99_ns) / 1e3,
                static_cast<long long>(safe));
  return line;
}

void StatusLine::tick() {
  if (!enabled_) return;
  const std::int64_t updates = status_.updates.load(std::memory_order_acquire);
  if (updates == seen_) return;
  seen_ = updates;
  const std::string line =
      format(rate_hz_, status_.cycles.load(std::memory_order_relaxed),
             status_.periods_planned.load(std::memory_order_relaxed),
             status_.deadline_misses.load(std::memory_order_relaxed),
             status_.safe_command_cycles.load(std::memory_order_relaxed),
             status_.round_trip_p99_ns.load(std::memory_order_relaxed), controller_process_);
  std::fprintf(stderr, "\r%s\033[K", line.c_str());  // \033[K: clear what a longer line left
  std::fflush(stderr);
  printed_ = true;
}

void StatusLine::finish() {
  if (printed_) std::fputc('\n', stderr);
  printed_ = false;
}

}  // namespace flexloop::hil
