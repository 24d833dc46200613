// SPDX-License-Identifier: BSD-3-Clause
#include "rt/event_log_recorder.hpp"

#include <lcm/eventlog.h>
#include <pthread.h>
#include <sched.h>
#include <sys/sysinfo.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "common/input_error.hpp"
#include "rt/monotonic_time.hpp"

namespace flexloop::rt {

namespace {

std::int64_t wall_clock_now_ns() {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return static_cast<std::int64_t>(t.tv_sec) * kNsPerSecond + t.tv_nsec;
}

// The writer must not inherit the loop's real-time priority or its CPU: it runs whenever and
// wherever the loop leaves room.
void run_as_ordinary_thread() {
  sched_param normal{};
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
  cpu_set_t every;
  CPU_ZERO(&every);
  for (int cpu = 0; cpu < get_nprocs_conf() && cpu < CPU_SETSIZE; ++cpu) CPU_SET(cpu, &every);
  pthread_setaffinity_np(pthread_self(), sizeof every, &every);
}

}  // namespace

EventLogRecorder::EventLogRecorder(const std::string& path, int max_message_bytes, int capacity)
    : path_(path),
      max_message_bytes_(std::max(max_message_bytes, 0)),
      slot_bytes_(
          (sizeof(SlotHeader) + static_cast<std::size_t>(std::max(max_message_bytes, 0)) + 63) /
          64 * 64),
      capacity_(static_cast<std::uint64_t>(std::max(capacity, 1))),
      ring_(slot_bytes_ * capacity_) {
  lcm_eventlog_t* log = lcm_eventlog_create(path.c_str(), "w");
  if (log == nullptr)
    throw common::InputError(
        path, std::string("cannot be created for the LCM log (") + std::strerror(errno) + ")");
  log_ = log;
  // The writer hands the kernel the log in large blocks, not stdio's 4 KB ones.
  stdio_buffer_.resize(kWriteBlockBytes);
  std::setvbuf(log->f, stdio_buffer_.data(), _IOFBF, stdio_buffer_.size());
  channels_.reserve(kMaxChannels);  // never reallocated while the writer reads it
  wall_minus_monotonic_ns_ = wall_clock_now_ns() - monotonic_now_ns();
  writer_ = std::thread([this] {
    run_as_ordinary_thread();
    write_loop();
  });
}

EventLogRecorder::~EventLogRecorder() {
  finish();
}

int EventLogRecorder::channel(const std::string& name) {
  const auto it = std::find(channels_.begin(), channels_.end(), name);
  if (it != channels_.end()) return static_cast<int>(it - channels_.begin());
  if (channels_.size() == kMaxChannels)
    throw std::logic_error("EventLogRecorder: more than " + std::to_string(kMaxChannels) +
                           " channels");
  channels_.push_back(name);
  return static_cast<int>(channels_.size()) - 1;
}

void EventLogRecorder::record(int channel, const void* data, int size, std::int64_t t_ns) noexcept {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  if (size < 0 || size > max_message_bytes_ ||
      head - tail_.load(std::memory_order_acquire) >= capacity_) {
    ++dropped_;
    return;
  }
  std::uint8_t* s = slot(head);
  const SlotHeader h{t_ns, channel, size};
  std::memcpy(s, &h, sizeof h);
  std::memcpy(s + sizeof h, data, static_cast<std::size_t>(size));
  head_.store(head + 1, std::memory_order_release);
  ++recorded_;
}

void EventLogRecorder::write_loop() {
  auto* log = static_cast<lcm_eventlog_t*>(log_);
  std::int64_t eventnum = 0;
  for (;;) {
    // Read the stop flag first: everything recorded before it was set is written below.
    const bool last = stop_.load(std::memory_order_acquire);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    for (; tail < head; ++tail) {
      const std::uint8_t* s = slot(tail);
      SlotHeader h{};
      std::memcpy(&h, s, sizeof h);
      const std::string& name = channels_[static_cast<std::size_t>(h.channel)];
      lcm_eventlog_event_t e{};
      e.eventnum = eventnum++;
      e.timestamp = (h.t_ns + wall_minus_monotonic_ns_) / 1000;
      e.channellen = static_cast<std::int32_t>(name.size());
      e.datalen = h.size;
      e.channel = const_cast<char*>(name.c_str());
      e.data = const_cast<std::uint8_t*>(s + sizeof h);
      if (lcm_eventlog_write_event(log, &e) != 0 && error_.empty())
        error_ = path_ + ": writing the LCM log failed (" + std::strerror(errno) + ")";
      tail_.store(tail + 1, std::memory_order_release);
    }
    if (last) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

std::string EventLogRecorder::finish() {
  if (finished_) return error_;
  finished_ = true;
  stop_.store(true, std::memory_order_release);
  if (writer_.joinable()) writer_.join();
  auto* log = static_cast<lcm_eventlog_t*>(log_);
  if (log != nullptr) {
    // On the disk before the run reports it written, as the project's other outputs are.
    if ((std::fflush(log->f) != 0 || ::fsync(::fileno(log->f)) != 0) && error_.empty())
      error_ = path_ + ": writing the LCM log failed (" + std::strerror(errno) + ")";
    lcm_eventlog_destroy(log);
    log_ = nullptr;
  }
  return error_;
}

}  // namespace flexloop::rt
