// SPDX-License-Identifier: BSD-3-Clause
// rt/lcm_transport.hpp on LCM's in-process provider (memq://): no network, no multicast, so it
// runs anywhere. Publishing from the preallocated buffer, delivery into an inbox, and the three
// receive modes returning at their deadline or as soon as the predicate holds.
#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "rt/lcm_transport.hpp"
#include "tests/support/messages.hpp"

using namespace flexloop::rt;
using flexloop_msgs::sensor_sample_t;

namespace {

constexpr const char* kInProcessUrl = "memq://";
// Longer than std::string's small-buffer size on purpose (allocation-free path is the C API).
constexpr const char* kChannel = "FLEXLOOP_TEST_TRANSPORT_SAMPLES";

}  // namespace

TEST_CASE("published samples reach the inbox through handle_pending") {
  LcmTransport lcm(kInProcessUrl);
  MessageInbox<sensor_sample_t> inbox;
  lcm.subscribe(kChannel, inbox);
  LcmPublisher<sensor_sample_t> pub(lcm, kChannel);
  sensor_sample_t m = flexloop::test::sized_sample();
  for (int k = 1; k <= 3; ++k) {
    m.seq = k;
    m.sensors[2] = 0.5 * k;
    REQUIRE(pub.publish(m));
  }
  CHECK(lcm.handle_pending() == 3);
  CHECK(inbox.accepted() == 3);
  CHECK(inbox.superseded() == 2);  // newest wins
  const sensor_sample_t* got = inbox.take();
  REQUIRE(got != nullptr);
  CHECK(got->seq == 3);
  CHECK(got->sensors[2] == 1.5);
  CHECK(pub.published() == 3);
  CHECK(pub.failures() == 0);
  CHECK(lcm.handle_pending() == 0);
}

TEST_CASE("handle_until returns at the deadline when nothing comes, in every receive mode") {
  LcmTransport lcm(kInProcessUrl);
  MessageInbox<sensor_sample_t> inbox;
  lcm.subscribe(kChannel, inbox);
  for (const ReceiveMode mode :
       {ReceiveMode::kBlocking, ReceiveMode::kPolling, ReceiveMode::kHybrid}) {
    INFO("receive mode " << to_string(mode));
    const std::int64_t start = monotonic_now_ns();
    const std::int64_t deadline = start + 2'000'000;
    CHECK(lcm.handle_until(
              deadline, mode, [] { return false; }, start + 1'000'000) == 0);
    CHECK(monotonic_now_ns() >= deadline);
  }
}

TEST_CASE("handle_until stops as soon as the predicate holds, before its deadline") {
  LcmTransport lcm(kInProcessUrl);
  MessageInbox<sensor_sample_t> inbox;
  lcm.subscribe(kChannel, inbox);
  LcmPublisher<sensor_sample_t> pub(lcm, kChannel);
  for (const ReceiveMode mode :
       {ReceiveMode::kBlocking, ReceiveMode::kPolling, ReceiveMode::kHybrid}) {
    INFO("receive mode " << to_string(mode));
    sensor_sample_t m = flexloop::test::sized_sample();
    m.seq = inbox.accepted() + 1;
    REQUIRE(pub.publish(m));
    const std::int64_t far = monotonic_now_ns() + 10 * kNsPerSecond;
    CHECK(lcm.handle_until(far, mode, [&] { return inbox.has_fresh(); }) == 1);
    CHECK(monotonic_now_ns() < far);
    REQUIRE(inbox.take() != nullptr);
  }
}

TEST_CASE("receive modes parse from their command-line names") {
  CHECK(parse_receive_mode("hybrid") == ReceiveMode::kHybrid);
  CHECK(std::string(to_string(ReceiveMode::kBlocking)) == "block");
  CHECK_THROWS_WITH(parse_receive_mode("spin"), Catch::Contains("block | poll | hybrid"));
}
