// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A controller FMU's log messages (its fmi2CallbackLogger) without bookkeeping on the real-time
// thread: the logger formats each message with vsnprintf into one slot of a ring allocated at
// start-up (no allocation, lock or system call; a message longer than a slot is cut), and the
// side that is not real-time takes them out afterwards (take(), at the end of the run or between
// runs). As the LCM log recorder (rt/event_log_recorder.hpp): one producer (the thread that calls
// the FMU), one consumer; a full ring drops the newest messages and counts them. The first
// message the FMU logs with fmi2Warning is also kept apart (a report names it).
#include <array>
#include <atomic>
#include <cstdarg>
#include <cstdint>
#include <string>
#include <vector>

#include "common/fmi2.h"

namespace flexloop::controller::fmu {

class FmuLogRing {
 public:
  static constexpr std::size_t kSlots = 64;
  static constexpr std::size_t kSlotChars = 256;

  /// `fmu`: the file, as the taken messages name it.
  explicit FmuLogRing(std::string fmu);
  FmuLogRing(const FmuLogRing&) = delete;
  FmuLogRing& operator=(const FmuLogRing&) = delete;

  /// The fmi2CallbackLogger (componentEnvironment: this ring).
  static void logger(fmi2ComponentEnvironment ring, fmi2String instance, fmi2Status status,
                     fmi2String category, fmi2String message, ...);

  /// Copies one formatted message into the ring. Never blocks or allocates.
  void record(fmi2String instance, fmi2Status status, fmi2String category, fmi2String message,
              std::va_list args) noexcept;

  /// The messages recorded since the last take, oldest first, each "FMU <file> (<instance>,
  /// <status>, <category>): <text>". Allocates: not on the real-time thread.
  std::vector<std::string> take();
  /// Messages dropped because the ring was full, since the start.
  std::int64_t lost() const noexcept { return lost_.load(std::memory_order_relaxed); }
  /// The text of the first message logged with fmi2Warning; empty while none was.
  std::string first_warning() const;

 private:
  struct Slot {
    fmi2Status status = fmi2OK;
    std::array<char, 64> instance{}, category{};
    std::array<char, kSlotChars> text{};
  };

  std::string fmu_;
  std::vector<Slot> slots_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // written by the producer
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // written by the consumer
  std::atomic<std::int64_t> lost_{0};
  std::array<char, kSlotChars> first_warning_{};
  std::atomic<bool> warned_{false};
};

}  // namespace flexloop::controller::fmu
