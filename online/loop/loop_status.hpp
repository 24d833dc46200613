// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant loop's once-a-second figures where a watching process can read them (hil's live
// status line): a few lock-free counters in memory shared across fork(). The plant writes them
// when it publishes loop_stats_t (relaxed stores, no syscall, no allocation); the controller
// process its sample in hand before each answer; the watcher reads them when it likes. Set-up only:
// SharedLoopStatus maps the page before the fork.
#include <atomic>
#include <cstdint>

namespace flexloop::loop {

struct LoopStatus {
  std::atomic<std::int64_t> updates{0};  ///< publications so far (0: nothing yet)
  std::atomic<std::int64_t> periods_planned{0};
  std::atomic<std::int64_t> cycles{0};
  std::atomic<std::int64_t> deadline_misses{0};
  std::atomic<std::int64_t> safe_command_cycles{0};
  std::atomic<std::int64_t> round_trip_p99_ns{0};
  /// Written by the controller process: the seq of the sample it is answering (-1: none yet), so
  /// that a controller that dies in its step is named with the sample.
  std::atomic<std::int64_t> controller_sample{-1};
  static_assert(std::atomic<std::int64_t>::is_always_lock_free);
};

/// A LoopStatus in an anonymous shared mapping: create it before fork(), and parent and child
/// see the same one. std::runtime_error when the mapping fails.
class SharedLoopStatus {
 public:
  SharedLoopStatus();
  ~SharedLoopStatus();
  SharedLoopStatus(const SharedLoopStatus&) = delete;
  SharedLoopStatus& operator=(const SharedLoopStatus&) = delete;

  LoopStatus* get() const noexcept { return status_; }

 private:
  LoopStatus* status_ = nullptr;
};

}  // namespace flexloop::loop
