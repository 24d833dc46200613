// SPDX-License-Identifier: BSD-3-Clause
// rt/event_log_recorder.hpp: what the loop records is in the LCM log, whole and in order, read
// back with LCM's own reader; what it could not keep (a full ring, an oversize message) is
// counted, never written half; a file that cannot be created is refused at once.
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "rt/event_log_recorder.hpp"
#include "rt/monotonic_time.hpp"

using flexloop::rt::EventLogRecorder;

namespace {

struct Read {
  std::vector<std::string> channels;
  std::vector<std::vector<std::uint8_t>> data;
  std::vector<std::int64_t> timestamps_us;
};

Read read_log(const std::string& path) {
  lcm::LogFile file(path, "r");
  REQUIRE(file.good());
  Read r;
  for (const lcm::LogEvent* e = file.readNextEvent(); e != nullptr; e = file.readNextEvent()) {
    r.channels.push_back(e->channel);
    const auto* bytes = static_cast<const std::uint8_t*>(e->data);
    r.data.emplace_back(bytes, bytes + e->datalen);
    r.timestamps_us.push_back(e->timestamp);
  }
  return r;
}

}  // namespace

TEST_CASE("event log: every recorded message is written whole, in order, with its channel",
          "[rt][log]") {
  const std::string path =
      (std::filesystem::temp_directory_path() / "flexloop_test_event_log.lcmlog").string();
  constexpr int messages = 20000;
  // A ring that holds them all (nothing may be lost), and a small one (the writer must keep up,
  // or the drops are counted).
  const int capacity = GENERATE(20000, 64);  // messages, and a small ring
  CAPTURE(capacity);
  std::int64_t recorded = 0, dropped = 0;
  {
    EventLogRecorder log(path, 64, capacity);
    const int even = log.channel("EVEN"), odd = log.channel("ODD");
    CHECK(log.channel("EVEN") == even);
    for (int i = 0; i < messages; ++i) {
      std::uint8_t payload[64];
      std::memset(payload, i & 0xff, sizeof payload);
      std::memcpy(payload, &i, sizeof i);
      log.record(i % 2 ? odd : even, payload, 8 + i % 57, flexloop::rt::monotonic_now_ns());
    }
    std::uint8_t too_long[80] = {};
    log.record(even, too_long, sizeof too_long, flexloop::rt::monotonic_now_ns());
    CHECK(log.finish().empty());
    recorded = log.recorded();
    dropped = log.dropped();
  }
  CHECK(recorded + dropped == messages + 1);
  CHECK(dropped >= 1);  // the oversize message at least
  if (capacity == messages) CHECK(dropped == 1);
  const Read r = read_log(path);
  std::filesystem::remove(path);
  REQUIRE(static_cast<std::int64_t>(r.data.size()) == recorded);
  int previous = -1;
  for (std::size_t k = 0; k < r.data.size(); ++k) {
    int i = 0;
    std::memcpy(&i, r.data[k].data(), sizeof i);
    INFO("event " << k << ", message " << i);
    CHECK(i > previous);  // in order; a dropped message leaves a gap, never a reordering
    CHECK(r.channels[k] == (i % 2 ? "ODD" : "EVEN"));
    CHECK(r.data[k].size() == static_cast<std::size_t>(8 + i % 57));
    CHECK(r.data[k].back() == (i & 0xff));
    if (k > 0) CHECK(r.timestamps_us[k] >= r.timestamps_us[k - 1]);
    previous = i;
  }
}

TEST_CASE("event log: a file that cannot be created is refused, naming it", "[rt][log]") {
  const std::string dir = std::filesystem::temp_directory_path().string();
  CHECK_THROWS_WITH(EventLogRecorder(dir, 64, 16),
                    Catch::Contains(dir) && Catch::Contains("cannot be created"));
}
