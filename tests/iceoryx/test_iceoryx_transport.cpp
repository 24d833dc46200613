// SPDX-License-Identifier: BSD-3-Clause
// rt/iceoryx_transport.hpp against a real RouDi (rt/roudi_process.hpp): a message sent through
// the iceoryx carrier arrives as exactly the bytes LCM's encode makes of it (read both through
// the carrier's inbox and through a raw iceoryx subscriber on the same service), decodes equal,
// wakes a blocking wait (the WaitSet), and a publish + receive cycle allocates nothing once
// running. The iceoryx endpoints run in a child: the process that owns RouDi never registers.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <vector>

#include "rt/iceoryx_transport.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/roudi_process.hpp"
#include "rt/thread_allocations.hpp"
#include "tests/iceoryx/child_outcome.hpp"
#include "tests/support/dev_shm.hpp"

using namespace flexloop::rt;
using flexloop_msgs::sensor_sample_t;

namespace {

constexpr const char* kChannel = "FLEXLOOP_TEST_CARRIER";

enum Outcome {
  kEqual = 0,
  kNoConnection = 2,
  kBytesDiffer = 3,
  kDecodedDiffer = 4,
  kBlockingWaitMissed = 5,
  kAllocated = 6,
  kPublishFailed = 7,
};

sensor_sample_t sample(std::int64_t seq) {
  sensor_sample_t m{};
  m.seq = seq;
  m.t_ns = 1'000 * seq;
  m.plant_epoch = 42;
  m.n_sensors = 3;
  m.sensors = {1.5, -2.25, 1e-300};
  m.n_performance = 2;
  m.performance = {0.125, 7.0};
  m.applied_seq = seq - 1;
  m.applied_scale = 0.5;
  return m;
}

std::vector<std::uint8_t> lcm_encoded(const sensor_sample_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

bool same_sample(const sensor_sample_t& a, const sensor_sample_t& b) {
  return a.seq == b.seq && a.t_ns == b.t_ns && a.plant_epoch == b.plant_epoch &&
         a.sensors == b.sensors && a.performance == b.performance &&
         a.applied_seq == b.applied_seq && a.applied_scale == b.applied_scale;
}

// Takes the next chunk of the raw subscriber as bytes (empty when none within 1 s).
std::vector<std::uint8_t> take_raw(iox::popo::UntypedSubscriber& raw) {
  const std::int64_t give_up = monotonic_now_ns() + kNsPerSecond;
  std::vector<std::uint8_t> bytes;
  while (bytes.empty() && monotonic_now_ns() < give_up)
    raw.take().and_then([&](const void* p) {
      const auto* c = static_cast<const std::uint8_t*>(p);
      bytes.assign(c, c + iox::mepoo::ChunkHeader::fromUserPayload(p)->userPayloadSize());
      raw.release(p);
    });
  return bytes;
}

// The child's whole run: connect, compare bytes and fields, then count a cycle's allocations.
int exchange() {
  IceoryxTransport carrier("flexloop_test_carrier");
  MessageInbox<sensor_sample_t> inbox;
  carrier.subscribe(kChannel, inbox, 4);
  iox::popo::SubscriberOptions raw_options;
  raw_options.queueCapacity = 4;
  iox::popo::UntypedSubscriber raw(iceoryx_service(kChannel), raw_options);
  IceoryxPublisher<sensor_sample_t> pub(carrier, kChannel);
  std::int64_t seq = 0;
  const auto fresh = [&] { return inbox.has_fresh() && inbox.newest().seq == seq; };
  const std::int64_t give_up = monotonic_now_ns() + 3 * kNsPerSecond;
  while (!fresh() || !raw.hasData()) {  // both subscribers connected (discovery takes some ms)
    if (monotonic_now_ns() > give_up) return kNoConnection;
    pub.publish(sample(++seq));
    carrier.handle_until(monotonic_now_ns() + 10'000'000, ReceiveMode::kPolling, fresh);
  }
  raw.releaseQueuedData();
  inbox.take();

  const sensor_sample_t m = sample(++seq);
  if (!pub.publish(m)) return kPublishFailed;
  if (take_raw(raw) != lcm_encoded(m)) return kBytesDiffer;
  carrier.handle_until(monotonic_now_ns() + kNsPerSecond, ReceiveMode::kBlocking, fresh);
  const sensor_sample_t* got = inbox.take();
  if (!got) return kBlockingWaitMissed;
  if (!same_sample(*got, m)) return kDecodedDiffer;

  sensor_sample_t next = m;
  const std::uint64_t before = thread_allocations();
  for (int i = 0; i < 200; ++i) {
    next.seq = ++seq;
    pub.publish(next);
    carrier.handle_until(monotonic_now_ns() + kNsPerSecond, ReceiveMode::kPolling, fresh);
    inbox.take();
    raw.releaseQueuedData();
  }
  if (thread_allocations() != before) return kAllocated;
  return kEqual;
}

}  // namespace

TEST_CASE(
    "iceoryx carrier: LCM's bytes arrive unchanged, decode equal, wake a blocking wait, "
    "and a cycle allocates nothing") {
  const auto shm_before = flexloop::test::dev_shm_entries();
  RoudiOptions o;
  o.mempools =
      mempools_for_messages(static_cast<std::size_t>(max_encoded_size<sensor_sample_t>()), 64);
  RoudiProcess roudi(o);
  CHECK(flexloop::test::outcome_in_child(exchange, 20 * kNsPerSecond) == kEqual);
#ifdef FLEXLOOP_COUNTS_ALLOCATIONS
  CHECK(allocations_counted());  // else the allocation check above would be empty
#endif
  roudi.stop();
  CHECK(flexloop::test::dev_shm_entries() == shm_before);
}
