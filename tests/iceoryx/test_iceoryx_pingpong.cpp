// SPDX-License-Identifier: BSD-3-Clause
// rt/iceoryx_pingpong_baseline.hpp without timing judgement (it runs beside other tests, at
// SCHED_OTHER, sleeping between pings): every ping is accounted for once, each answered one has a
// round trip, and nothing is left behind; RouDi killed in the middle of the run is an error
// naming it, within the run's time and not a hang, and still nothing is left behind.
#include <signal.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <set>
#include <string>
#include <thread>

#include "rt/iceoryx_pingpong_baseline.hpp"
#include "rt/message_validation.hpp"
#include "rt/monotonic_time.hpp"
#include "tests/support/dev_shm.hpp"

using namespace flexloop::rt;
using flexloop::test::dev_shm_entries;

namespace {

PingPongOptions gentle(std::int64_t duration_ns) {
  PingPongOptions o;
  o.clock.period_ns = 2'000'000;  // 500 Hz
  o.clock.wait_mode = WaitMode::kSleep;
  o.receive_mode = ReceiveMode::kBlocking;
  o.duration_ns = duration_ns;
  o.ping_realtime = {.cpu = 0, .lock_memory = false, .fifo_priority = 0};
  o.pong_realtime = {.cpu = 1, .lock_memory = false, .fifo_priority = 0};
  return o;
}

RoudiOptions sized_for_the_messages() {
  RoudiOptions o;
  o.mempools = mempools_for_messages(
      static_cast<std::size_t>(max_encoded_size<flexloop_msgs::sensor_sample_t>()), 128);
  return o;
}

// Sockets iceoryx runtimes leave in /tmp when they cannot deregister (named after the runtime).
std::set<std::string> runtime_sockets() {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator("/tmp"))
    if (e.path().filename().string().rfind("flexloop_p", 0) == 0)
      names.insert(e.path().filename().string());
  return names;
}

}  // namespace

TEST_CASE("iceoryx ping-pong: every ping accounted for once, nothing left behind") {
  const auto shm_before = dev_shm_entries();
  const auto sockets_before = runtime_sockets();
  PingPongResult r;
  {
    RoudiProcess roudi(sized_for_the_messages());
    r = run_iceoryx_pingpong_baseline(gentle(400'000'000), roudi);
  }
  CHECK(r.sent > 0);  // 200 periods; a period skipped under load sends nothing
  CHECK(r.sent <= 200);
  CHECK(r.answered + r.unanswered == r.sent);
  CHECK(r.answered > 0);
  CHECK(r.round_trip->count() == r.answered);
  CHECK(r.round_trip->min() > 0);
  CHECK(r.ping_drops.total() == 0);
  CHECK_THAT(r.pong_summary, Catch::Contains("0 publish failures"));
  CHECK_THAT(r.pong_setup, Catch::Contains("CPU 1"));
  CHECK(dev_shm_entries() == shm_before);
  CHECK(runtime_sockets() == sockets_before);
  CHECK_FALSE(running_roudi_pid().has_value());
}

TEST_CASE("iceoryx ping-pong: RouDi killed mid-run is an error naming it, not a hang") {
  const auto shm_before = dev_shm_entries();
  RoudiProcess roudi(sized_for_the_messages());
  const pid_t pid = roudi.pid();
  std::thread killer([pid] {
    usleep(300'000);
    kill(pid, SIGKILL);
  });
  const std::int64_t start = monotonic_now_ns();
  CHECK_THROWS_WITH(run_iceoryx_pingpong_baseline(gentle(1'000'000'000), roudi),
                    Catch::Contains("iox-roudi (pid " + std::to_string(pid) + ")") &&
                        Catch::Contains("killed by signal 9") &&
                        Catch::Contains("during the iceoryx ping-pong"));
  killer.join();
  // The run's own time (connect 3 s + 1 s) and the grace for its processes, not more.
  CHECK(monotonic_now_ns() - start < 20 * kNsPerSecond);
  roudi.stop();
  CHECK(dev_shm_entries() == shm_before);
  CHECK_FALSE(running_roudi_pid().has_value());
}
