// SPDX-License-Identifier: BSD-3-Clause
#include "rt/shm_pingpong_baseline.hpp"

#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>

#include "rt/reap_child.hpp"

namespace flexloop::rt {

namespace {

// Spins between two looks at the clock while waiting (a look costs ~20 ns; a round trip ~500).
constexpr int kSpinsPerClockLook = 1024;
constexpr std::int64_t kStop = -1;  // the ping word's value that ends the pong

// The shared page: the two words on one cache line, the pong's set-up text on lines of its own.
struct SharedPage {
  alignas(64) std::atomic<std::int64_t> ping{0};
  std::atomic<std::int64_t> pong{0};
  alignas(64) std::atomic<int> pong_ready{0};  // 1: set up, text written; 2: failed
  char pong_setup[2048]{};
};
static_assert(sizeof(SharedPage) <= 4096, "one page");
static_assert(std::atomic<std::int64_t>::is_always_lock_free, "lock-free across processes");

// Spins until `word` reads `want`; false when `give_up_ns` passed without it.
bool spin_until(const std::atomic<std::int64_t>& word, std::int64_t want, std::int64_t give_up_ns) {
  for (;;) {
    for (int i = 0; i < kSpinsPerClockLook; ++i)
      if (word.load(std::memory_order_acquire) == want) return true;
    if (monotonic_now_ns() > give_up_ns) return false;
  }
}

void copy_text(char* to, std::size_t size, const std::string& text) {
  std::snprintf(to, size, "%s", text.c_str());
}

// The child: echo every new ping value until told to stop, or until the ping stops moving.
int run_pong(SharedPage& page, const ShmPingPongOptions& o) {
  copy_text(page.pong_setup, sizeof page.pong_setup,
            apply_realtime_setup(o.pong_realtime).describe());
  page.pong_ready.store(1, std::memory_order_release);
  std::int64_t last = 0;
  std::int64_t give_up = monotonic_now_ns() + o.give_up_ns;
  for (;;) {
    int spins = 0;
    std::int64_t now = 0;
    while ((now = page.ping.load(std::memory_order_acquire)) == last) {
      if (++spins < kSpinsPerClockLook) continue;
      spins = 0;
      if (monotonic_now_ns() > give_up) return 1;  // the ping is gone or starved
    }
    if (now == kStop) return 0;
    page.pong.store(now, std::memory_order_release);
    last = now;
    give_up = monotonic_now_ns() + o.give_up_ns;
  }
}

// The parent: warm up, then record round trips back to back.
void run_ping(SharedPage& page, const ShmPingPongOptions& o, ShmPingPongResult& r) {
  const std::int64_t ready_by = monotonic_now_ns() + o.give_up_ns;
  while (page.pong_ready.load(std::memory_order_acquire) == 0) {
    if (monotonic_now_ns() > ready_by)
      throw std::runtime_error("shared-memory ping-pong: the pong process did not start within " +
                               std::to_string(o.give_up_ns / 1'000'000) + " ms");
    usleep(100);
  }
  r.pong_setup = page.pong_setup;
  if (page.pong_ready.load(std::memory_order_acquire) != 1)
    throw std::runtime_error("shared-memory ping-pong: the pong process failed: " + r.pong_setup);
  r.ping_setup = apply_realtime_setup(o.ping_realtime).describe();
  LatencyHistogram& rtt = *r.round_trip;
  const std::int64_t total = o.warm_up + o.round_trips;
  for (std::int64_t i = 1; i <= total; ++i) {
    const std::int64_t sent = monotonic_now_ns();
    page.ping.store(i, std::memory_order_release);
    if (!spin_until(page.pong, i, sent + o.give_up_ns))
      throw std::runtime_error(
          "shared-memory ping-pong: the pong process stopped answering at "
          "round trip " +
          std::to_string(i) + " (no answer within " + std::to_string(o.give_up_ns / 1'000'000) +
          " ms)");
    if (i > o.warm_up) rtt.record(monotonic_now_ns() - sent);
  }
  r.round_trips = rtt.count();
}

}  // namespace

ShmPingPongResult run_shm_pingpong_baseline(const ShmPingPongOptions& options) {
  if (options.round_trips < 1 || options.warm_up < 0 || options.give_up_ns <= 0)
    throw std::invalid_argument(
        "shared-memory ping-pong: round trips >= 1, warm-up >= 0 and a positive give-up time");
  ShmPingPongResult r;
  r.round_trip = std::make_unique<LatencyHistogram>();
  void* map =
      mmap(nullptr, sizeof(SharedPage), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED)
    throw std::runtime_error(std::string("shared-memory ping-pong: mmap: ") + std::strerror(errno));
  SharedPage& page = *new (map) SharedPage;
  const pid_t parent = getpid();
  std::fflush(nullptr);  // nothing buffered may be written twice
  const pid_t child = fork();
  if (child < 0) {
    munmap(map, sizeof(SharedPage));
    throw std::runtime_error("shared-memory ping-pong: fork failed");
  }
  if (child == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);  // a ping that dies takes its pong along
    int code = 1;
    if (getppid() == parent) {
      try {
        code = run_pong(page, options);
      } catch (const std::exception& e) {
        copy_text(page.pong_setup, sizeof page.pong_setup, e.what());
        page.pong_ready.store(2, std::memory_order_release);
      }
    }
    _exit(code);  // the parent's atexit handlers and buffers are not the child's to run
  }
  try {
    run_ping(page, options, r);
  } catch (...) {
    reap_child(child, 0);
    munmap(map, sizeof(SharedPage));
    throw;
  }
  page.ping.store(kStop, std::memory_order_release);
  reap_child(child, 2 * kNsPerSecond);
  munmap(map, sizeof(SharedPage));
  return r;
}

}  // namespace flexloop::rt
