// SPDX-License-Identifier: BSD-3-Clause
// rt/lcm_direct_socket.hpp: the loop thread reads LCM's multicast datagrams itself. In a private
// loopback-only namespace (entered in-process, as `flexloop hil --netns` does; each ctest case is
// its own process): what LCM publishes arrives intact through the direct socket, LCM's own
// subscribers on the same port still get every message, LCM starts no receive thread for the
// direct transport, and datagrams that are not LCM's are counted and skipped.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "online/loop/private_network.hpp"
#include "rt/lcm_transport.hpp"
#include "rt/loopback_guard.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/realtime_setup.hpp"
#include "tests/support/messages.hpp"

using namespace flexloop;
using flexloop_msgs::sensor_sample_t;

TEST_CASE("LCM URLs: group, port and receive buffer are read, a bad URL is refused") {
  const rt::UdpmAddress a =
      rt::parse_udpm_url("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=2097152");
  CHECK(a.group == "239.255.76.67");
  CHECK(a.port == 7667);
  CHECK(a.recv_buf_size == 2097152);
  CHECK(rt::parse_udpm_url("udpm://239.1.2.3").port == 7667);
  CHECK_THROWS_WITH(rt::parse_udpm_url("memq://"), Catch::Contains("needs a udpm:// URL"));
  CHECK_THROWS_WITH(rt::parse_udpm_url("udpm://10.0.0.1:7667"),
                    Catch::Contains("not an IPv4 multicast group"));
  CHECK_THROWS_WITH(rt::parse_udpm_url("udpm://239.1.2.3:70000"), Catch::Contains("port"));
  CHECK_THROWS_WITH(rt::parse_udpm_url("udpm://239.1.2.3:x"), Catch::Contains("whole number"));
}

TEST_CASE(
    "direct receive: LCM's messages arrive through the loop's own socket, LCM's subscribers "
    "still get them, foreign datagrams are skipped") {
  try {
    loop::enter_private_loopback_namespace();
  } catch (const std::exception& e) {
    WARN("skipped: cannot enter a private network namespace: " << e.what());
    return;
  }
  rt::require_private_loopback_namespace("direct receive test");
  const std::string url = rt::kPrivateLoopbackLcmUrl;
  rt::LcmTransport classic(url, rt::ReceivePath::kLcmThread);
  // The direct transport starts no thread of LCM's: not on creation, subscription or publishing.
  const std::vector<pid_t> threads_before = rt::process_thread_ids();
  rt::LcmTransport direct(url, rt::ReceivePath::kDirect);
  rt::MessageInbox<sensor_sample_t> direct_inbox, classic_inbox;
  direct.subscribe("FLEXLOOP_DIRECT_TEST", direct_inbox);
  classic.subscribe("FLEXLOOP_DIRECT_TEST", classic_inbox);
  REQUIRE(rt::LcmPublisher<sensor_sample_t>(direct, "FLEXLOOP_DIRECT_SELF").publish({}));
  CHECK(rt::process_thread_ids() == threads_before);
  rt::LcmPublisher<sensor_sample_t> pub(classic, "FLEXLOOP_DIRECT_TEST");
  rt::LcmPublisher<sensor_sample_t> other(classic, "FLEXLOOP_SOMETHING_ELSE");

  // A datagram that is not LCM's, to the same group and port.
  const int raw = socket(AF_INET, SOCK_DGRAM, 0);
  REQUIRE(raw >= 0);
  const unsigned char ttl = 0;
  setsockopt(raw, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(7667);
  inet_pton(AF_INET, "239.255.76.67", &to.sin_addr);
  const char junk[] = "not an LCM packet at all";
  REQUIRE(sendto(raw, junk, sizeof junk, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) > 0);
  close(raw);

  sensor_sample_t m = test::sized_sample();
  m.plant_epoch = 5;
  for (int k = 1; k <= 200; ++k) {
    m.seq = k;
    m.t_ns = rt::monotonic_now_ns();
    m.sensors[k % 6] = 0.25 * k;
    m.performance[(k + 1) % 6] = -1e-3 * k;
    REQUIRE(pub.publish(m));
    if (k % 10 == 0) REQUIRE(other.publish(m));
    const std::int64_t until = rt::monotonic_now_ns() + 200'000'000;
    direct.handle_until(until, rt::ReceiveMode::kBlocking,
                        [&] { return direct_inbox.has_fresh(); });
    classic.handle_until(until, rt::ReceiveMode::kBlocking,
                         [&] { return classic_inbox.has_fresh(); });
    const sensor_sample_t* d = direct_inbox.take();
    const sensor_sample_t* c = classic_inbox.take();
    REQUIRE(d != nullptr);
    REQUIRE(c != nullptr);
    CHECK(d->seq == k);
    CHECK(c->seq == k);
    CHECK(d->sensors == m.sensors);
    CHECK(d->performance == m.performance);
  }
  direct.handle_pending();
  CHECK(direct_inbox.accepted() == 200);
  CHECK(direct_inbox.drops().total() == 0);
  CHECK(direct.direct_socket()->foreign() == 1);
  // The 20 on the other channel, and LCM's own self-test message(s) (channel LCM_SELF_TEST).
  CHECK(direct.direct_socket()->unsubscribed() >= 20);
}
