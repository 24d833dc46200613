// SPDX-License-Identifier: BSD-3-Clause
// rt/realtime_setup.hpp: each step either does what it says (checked with the kernel's own
// view: sched_getcpu, sched_getscheduler) or reports why not; refused steps never throw.
#include <sched.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <thread>

#include "rt/denormals.hpp"
#include "rt/realtime_setup.hpp"

using namespace flexloop::rt;

namespace {

void check_refused(const SetupStatus& s, const char* why) {
  CHECK_FALSE(s.ok);
  CHECK_THAT(s.message, Catch::Contains(why));
}

}  // namespace

TEST_CASE("pinning moves the thread onto that CPU, a CPU that does not exist is refused") {
  std::thread t([] {
    const SetupStatus s = pin_current_thread_to_cpu(0);
    CHECK(s.ok);
    CHECK(sched_getcpu() == 0);
    check_refused(pin_current_thread_to_cpu(4096), "does not exist");
  });
  t.join();
}

TEST_CASE("SCHED_FIFO is granted (and visible to the kernel) or refused with the reason") {
  std::thread t([] {
    const SetupStatus s = try_set_fifo_priority(10);
    CHECK_FALSE(s.message.empty());
    if (s.ok) {
      CHECK(sched_getscheduler(0) == SCHED_FIFO);
    } else {
      CHECK(sched_getscheduler(0) == SCHED_OTHER);
      check_refused(s, "not permitted");
    }
    check_refused(try_set_fifo_priority(100), "outside");
  });
  t.join();
}

TEST_CASE("apply_realtime_setup reports every step it was asked for") {
  std::thread t([] {
    const RealtimeReport r =
        apply_realtime_setup({.cpu = 0, .lock_memory = false, .fifo_priority = 0});
    CHECK(r.affinity.ok);
    CHECK(r.memory.message.empty());  // not asked
    CHECK_FALSE(r.fifo);
    CHECK_THAT(r.priority.message, Catch::Contains("timer slack"));
    CHECK_THAT(r.describe(), Catch::Contains("pinned"));
  });
  t.join();
}

TEST_CASE("CpuDmaLatencyHold holds the device or says why not") {
  const CpuDmaLatencyHold hold;
  CHECK_FALSE(hold.message().empty());
  if (hold.active())
    CHECK_THAT(hold.message(), Catch::Contains("held at 0"));
  else
    CHECK_THAT(hold.message(), Catch::Contains("not held"));
}

TEST_CASE("process_thread_ids sees a thread appear and go") {
  const auto before = process_thread_ids();
  CHECK(std::find(before.begin(), before.end(), getpid()) != before.end());
  std::size_t during = 0;
  std::thread t([&] { during = process_thread_ids().size(); });
  t.join();
  CHECK(during == before.size() + 1);
}

TEST_CASE("apply_realtime_setup flushes denormals on the loop thread, and only there") {
  // volatile: the compiler must not fold the products at compile time (no FTZ there).
  volatile float tiny = 1e-30f, subnormal = 1e-40f;  // 1e-40f is below FLT_MIN (1.18e-38)
  REQUIRE(std::fpclassify(subnormal) == FP_SUBNORMAL);
  std::thread t([&] {
    CHECK_FALSE(denormals_flushed());
    CHECK(tiny * 1e-10f != 0.0f);  // gradual underflow: a subnormal result
    const RealtimeReport r = apply_realtime_setup({.lock_memory = false, .fifo_priority = 0});
    CHECK(r.denormals.ok);
    CHECK_THAT(r.describe(), Catch::Contains("denormals flushed to zero"));
    CHECK(denormals_flushed());
    CHECK(tiny * 1e-10f == 0.0f);                           // FTZ: a subnormal result becomes 0
    CHECK(subnormal * 1.0f == 0.0f);                        // DAZ: a subnormal operand is read as 0
    std::thread child([] { CHECK(denormals_flushed()); });  // inherited by threads it creates
    child.join();
  });
  t.join();
  CHECK_FALSE(denormals_flushed());  // the test runner's own thread is untouched
}
