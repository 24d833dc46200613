// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Records what a loop process sends and receives over LCM into an LCM log file (the format of
// lcm-logger: lcm-logplayer, lcm-spy and `flexloop log` read it), from inside the process.
//
// Why not the distribution's lcm-logger: at 10 kHz it is one more receiver competing for the
// loop's two CPUs; measured on this project's VMs it recorded about 40 % of a 3 s run's samples
// and raised the loop's misses from 0.3 % to 1.1-1.6 % (2026-12-03). Here the loop thread copies
// each message into a ring it allocated at start-up (no allocation, lock or system call in the
// loop: record() is a copy and an atomic store), and a writer thread at ordinary priority, on
// any CPU, writes the ring out in batches whenever the loop leaves it the CPU. A ring that fills
// (the writer kept off the CPU for longer than the ring lasts) drops the newest messages and
// counts them. At finish() the log is flushed and fsync'ed: written means on the disk.
//
// One producer (the loop thread) and one consumer (the writer thread).
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

namespace flexloop::rt {

class EventLogRecorder {
 public:
  /// Creates `path` (replacing it) and starts the writer. max_message_bytes: the largest message
  /// record() will be given; capacity: messages the ring holds. flexloop::common::InputError
  /// naming the path when it cannot be created (exit 2, as any output that cannot be written).
  EventLogRecorder(const std::string& path, int max_message_bytes, int capacity);
  ~EventLogRecorder();
  EventLogRecorder(const EventLogRecorder&) = delete;
  EventLogRecorder& operator=(const EventLogRecorder&) = delete;

  static constexpr std::size_t kMaxChannels = 16;
  /// Start-up: the id record() takes for `channel` (the same id for the same name), at most
  /// kMaxChannels of them.
  int channel(const std::string& name);

  /// Copies one message for the log, stamped with `t_ns` (CLOCK_MONOTONIC; the log holds wall
  /// time). Never blocks: when the ring is full, or the message longer than max_message_bytes,
  /// it is dropped and counted.
  void record(int channel, const void* data, int size, std::int64_t t_ns) noexcept;

  /// Stops the writer once it has written everything recorded, and closes the file. Empty when
  /// every write succeeded, else what went wrong. Called by the destructor if not before.
  std::string finish();

  std::int64_t recorded() const noexcept { return recorded_; }  ///< accepted by record()
  std::int64_t dropped() const noexcept { return dropped_; }
  const std::string& path() const noexcept { return path_; }

 private:
  struct SlotHeader {
    std::int64_t t_ns;
    std::int32_t channel;
    std::int32_t size;
  };
  static constexpr std::size_t kWriteBlockBytes = std::size_t{1} << 20;
  void write_loop();
  std::uint8_t* slot(std::uint64_t index) noexcept {
    return ring_.data() + (index % capacity_) * slot_bytes_;
  }

  std::string path_;
  int max_message_bytes_ = 0;
  void* log_ = nullptr;  // lcm_eventlog_t*
  std::vector<std::string> channels_;
  std::size_t slot_bytes_ = 0;
  std::uint64_t capacity_ = 0;
  std::vector<std::uint8_t> ring_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // written by the producer
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // written by the consumer
  std::atomic<bool> stop_{false};
  std::int64_t recorded_ = 0, dropped_ = 0;
  std::int64_t wall_minus_monotonic_ns_ = 0;
  std::string error_;
  std::vector<char> stdio_buffer_;  // the log file's buffer: outlives the file
  std::thread writer_;
  bool finished_ = false;
};

}  // namespace flexloop::rt
