// SPDX-License-Identifier: BSD-3-Clause
// No allocation when the loop records a message for its LCM log (rt/event_log_recorder.hpp):
// record() is a copy into the ring allocated at start-up, whether the ring takes the message or
// is full and counts it dropped. The writer thread (which allocates as it likes) is not counted:
// the count is the recording thread's own.
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <string>

#include "rt/event_log_recorder.hpp"
#include "rt/monotonic_time.hpp"
#include "tests/support/allocation_counter.hpp"

TEST_CASE("LCM log recorder: recording allocates nothing, kept or dropped", "[alloc][log]") {
  const std::string path =
      (std::filesystem::temp_directory_path() / "flexloop_test_log_allocations.lcmlog").string();
  const int capacity = GENERATE(40000, 2);  // keeps everything; full almost at once
  CAPTURE(capacity);
  flexloop::rt::EventLogRecorder recorder(path, 256, capacity);
  const int sensor = recorder.channel("FLEXLOOP_SENSOR");
  const int command = recorder.channel("FLEXLOOP_COMMAND");
  std::uint8_t payload[256] = {};
  const std::uint64_t before = flexloop::test::allocation_count();
  for (int i = 0; i < 20000; ++i) {
    payload[0] = static_cast<std::uint8_t>(i);
    recorder.record(sensor, payload, 200, flexloop::rt::monotonic_now_ns());
    recorder.record(command, payload, 120, flexloop::rt::monotonic_now_ns());
  }
  CHECK(flexloop::test::allocation_count() - before == 0);
  CHECK(recorder.finish().empty());
  CHECK(recorder.recorded() + recorder.dropped() == 40000);
  if (capacity == 2)
    CHECK(recorder.dropped() > 0);
  else
    CHECK(recorder.dropped() == 0);
  std::filesystem::remove(path);
}
