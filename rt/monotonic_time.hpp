// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The one time base of the online code: CLOCK_MONOTONIC in integer nanoseconds. Plant and
// controller processes on one machine share it, so a timestamp taken in one process can be
// compared with "now" in the other (round trips, message age). Never jumps with wall-clock
// changes. Reading it is a vDSO call: no system call, no allocation, no lock.
#include <time.h>

#include <cstdint>

namespace flexloop::rt {

inline constexpr std::int64_t kNsPerSecond = 1'000'000'000;

/// CLOCK_MONOTONIC now, ns.
inline std::int64_t monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerSecond + ts.tv_nsec;
}

/// ns -> timespec (ns >= 0) for clock_nanosleep / ppoll.
inline timespec to_timespec(std::int64_t ns) {
  return timespec{static_cast<time_t>(ns / kNsPerSecond), static_cast<long>(ns % kNsPerSecond)};
}

}  // namespace flexloop::rt
