// SPDX-License-Identifier: BSD-3-Clause
// The parts of a message's way through each carrier, on one core, without a second process: what
// a round trip costs besides the crossing from one core to the other (doc/performance.md, "The
// latency budget per transport"). Per message, the metrology frame's sample (6 + 6 channels):
//   - BM_InboxOffer: the receiving side's decode and checks (rt/message_inbox.hpp), the same on
//     both carriers; each message a new seq (encode included: BM_EncodeSensorSample in
//     bench_messages gives that part);
//   - BM_IceoryxPublishReceive: loan, encode, publish, then hasData, take, decode and checks,
//     release -- the whole of both ends of an iceoryx message in one process;
//   - BM_LcmPublishReceive: encode and sendmsg on loopback multicast, then ppoll, recvmsg, decode
//     and checks (the direct receive path) -- both ends of an LCM message, the kernel's UDP path
//     included, in one process.
// The iceoryx case needs a RouDi: start one first (`flexloop roudi &`; it is skipped otherwise).
// The LCM case enters a private loopback-only network namespace itself (root; skipped otherwise).
// Run alone on a quiet host:
//   flexloop roudi & taskset -c 0 build/bench/tests/bench/bench_transport; kill %1
#include <benchmark/benchmark.h>

#include <flexloop_msgs/sensor_sample_t.hpp>
#include <memory>
#include <string>

#include "online/loop/private_network.hpp"
#include "rt/iceoryx_transport.hpp"
#include "rt/lcm_transport.hpp"
#include "rt/loop_transport.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/roudi_process.hpp"
#include "tests/support/messages.hpp"

namespace {

using flexloop_msgs::sensor_sample_t;
using namespace flexloop;

// Encodes one sample with a new seq into buffer; its size.
int encode_next(sensor_sample_t& m, std::uint8_t* buffer, int capacity) {
  ++m.seq;
  return m.encode(buffer, 0, capacity);
}

void BM_InboxOffer(benchmark::State& state) {
  rt::MessageInbox<sensor_sample_t> inbox;
  auto m = test::sized_sample(6, 6);
  std::uint8_t buffer[256];
  for (auto _ : state) {
    const int n = encode_next(m, buffer, sizeof buffer);
    benchmark::DoNotOptimize(inbox.offer(buffer, n, rt::monotonic_now_ns()));
    benchmark::DoNotOptimize(inbox.take());
  }
  if (inbox.accepted() != static_cast<std::int64_t>(state.iterations()))
    state.SkipWithError("the inbox dropped messages");
}
BENCHMARK(BM_InboxOffer);

void BM_IceoryxPublishReceive(benchmark::State& state) {
  if (!rt::running_roudi_pid()) {
    state.SkipWithError("no RouDi runs: start `flexloop roudi &` first");
    return;
  }
  // One runtime per process, registered once (the static lives until the program ends).
  static rt::IceoryxTransport transport("bench_transport");
  static rt::MessageInbox<sensor_sample_t> inbox;
  static bool subscribed = false;
  const std::string channel = "FLEXLOOP_BENCH_TRANSPORT";
  if (!subscribed) transport.subscribe(channel, inbox);
  subscribed = true;
  rt::IceoryxPublisher<sensor_sample_t> publisher(transport, channel);
  // RouDi's discovery connects them within its 100 ms cycle.
  if (rt::wait_until_connected(
          [&] { return publisher.has_subscribers() && transport.subscriptions_connected(); },
          2 * rt::kNsPerSecond) < 0) {
    state.SkipWithError("RouDi did not connect the publisher and the subscriber within 2 s");
    return;
  }
  auto m = test::sized_sample(6, 6);
  m.seq = inbox.accepted() + 1000;  // after whatever an earlier run of this case sent
  for (auto _ : state) {
    ++m.seq;
    publisher.publish(m);
    benchmark::DoNotOptimize(transport.handle_pending());
    benchmark::DoNotOptimize(inbox.take());
  }
}
BENCHMARK(BM_IceoryxPublishReceive);

void BM_LcmPublishReceive(benchmark::State& state) {
  static bool in_namespace = false;
  if (!in_namespace) {
    try {
      loop::enter_private_loopback_namespace();
      in_namespace = true;
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
  rt::LcmTransport transport("udpm://239.255.76.67:7677?ttl=0", rt::ReceivePath::kDirect);
  rt::MessageInbox<sensor_sample_t> inbox;
  transport.subscribe("FLEXLOOP_BENCH_TRANSPORT", inbox);
  rt::LcmPublisher<sensor_sample_t> publisher(transport, "FLEXLOOP_BENCH_TRANSPORT");
  auto m = test::sized_sample(6, 6);
  for (auto _ : state) {
    ++m.seq;
    publisher.publish(m);
    while (transport.handle_pending() == 0) {
      // loopback delivers within the sendmsg call; a look that comes too early looks again
    }
    benchmark::DoNotOptimize(inbox.take());
  }
}
BENCHMARK(BM_LcmPublishReceive);

}  // namespace
