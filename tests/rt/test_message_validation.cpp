// SPDX-License-Identifier: BSD-3-Clause
// rt/message_validation.hpp and rt/message_inbox.hpp without a network: hand-encoded buffers
// are offered to an inbox; each drop reason is counted and the dropped message is never applied
// (newest() keeps the last good one).
#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <vector>

#include "rt/message_inbox.hpp"
#include "tests/support/messages.hpp"

using flexloop::rt::DropReason;
using flexloop::rt::EpochPolicy;
using flexloop::rt::MessageInbox;
using flexloop::rt::OrderGate;
using flexloop_msgs::actuator_command_t;
using flexloop_msgs::loop_stats_t;
using flexloop_msgs::sensor_sample_t;

namespace {

template <class Msg>
std::vector<std::uint8_t> encode(const Msg& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  REQUIRE(m.encode(buf.data(), 0, static_cast<int>(buf.size())) == static_cast<int>(buf.size()));
  return buf;
}

template <class Msg>
std::optional<DropReason> offer(MessageInbox<Msg>& inbox, const Msg& m, std::int64_t now = 0) {
  const auto buf = encode(m);
  return inbox.offer(buf.data(), static_cast<int>(buf.size()), now);
}

sensor_sample_t sample(std::int64_t epoch, std::int64_t seq, std::int64_t t_ns) {
  sensor_sample_t s = flexloop::test::sized_sample();
  s.plant_epoch = epoch;
  s.seq = seq;
  s.t_ns = t_ns;
  for (int i = 0; i < 6; ++i) {
    s.sensors[i] = static_cast<double>(seq) + i;
    s.performance[i] = -0.5 * i;
  }
  return s;
}

actuator_command_t command(std::int64_t epoch, std::int64_t answers, std::int64_t t_ns) {
  actuator_command_t c = flexloop::test::sized_command();
  c.plant_epoch = epoch;
  c.answers_seq = answers;
  c.seq = answers;
  c.t_ns = t_ns;
  for (int i = 0; i < 6; ++i) c.commands[i] = 0.25 * i;
  return c;
}

}  // namespace

TEST_CASE("a valid sensor sample is accepted, decoded bit for bit and taken once") {
  MessageInbox<sensor_sample_t> inbox;
  const auto s = sample(9, 1, 1000);
  CHECK_FALSE(offer(inbox, s, 1500).has_value());
  REQUIRE(inbox.has_fresh());
  const sensor_sample_t* got = inbox.take();
  REQUIRE(got != nullptr);
  CHECK(got->seq == 1);
  CHECK(got->sensors[5] == s.sensors[5]);
  CHECK(got->performance[3] == s.performance[3]);
  CHECK(inbox.newest_received_ns() == 1500);
  CHECK(inbox.take() == nullptr);
  CHECK(inbox.accepted() == 1);
  CHECK(inbox.drops().total() == 0);
}

TEST_CASE("truncated, over-long and foreign buffers are decode failures, never applied") {
  MessageInbox<sensor_sample_t> inbox;
  REQUIRE_FALSE(offer(inbox, sample(1, 1, 10)).has_value());
  inbox.take();
  auto buf = encode(sample(1, 2, 20));
  CHECK(inbox.offer(buf.data(), static_cast<int>(buf.size()) - 1, 0) == DropReason::kDecodeFailure);
  buf.push_back(0);
  CHECK(inbox.offer(buf.data(), static_cast<int>(buf.size()), 0) == DropReason::kDecodeFailure);
  const auto foreign = encode(command(1, 2, 20));  // another type: fingerprint differs
  CHECK(inbox.offer(foreign.data(), static_cast<int>(foreign.size()), 0) ==
        DropReason::kDecodeFailure);
  CHECK(inbox.offer(nullptr, 0, 0) == DropReason::kDecodeFailure);
  CHECK(inbox.drops()[DropReason::kDecodeFailure] == 4);
  CHECK_FALSE(inbox.has_fresh());
  CHECK(inbox.newest().seq == 1);
}

TEST_CASE("other channel counts than the loop's, or forged counts, are dropped before decoding") {
  // The plant expects 6 commands; the controller 6 sensors and any performance count.
  MessageInbox<actuator_command_t> commands(OrderGate(EpochPolicy::kFixed, 1), {6, 0});
  auto five = flexloop::test::sized_command(5);
  five.plant_epoch = 1;
  CHECK(offer(commands, five) == DropReason::kChannelCount);
  MessageInbox<sensor_sample_t> samples(OrderGate{}, {6, 0});
  auto s = flexloop::test::sized_sample(6, 9);
  s.seq = 1;
  CHECK_FALSE(offer(samples, s).has_value());
  s = flexloop::test::sized_sample(7, 6);
  s.seq = 2;
  CHECK(offer(samples, s) == DropReason::kChannelCount);
  // A count forged to -1 or 30000 in an otherwise valid buffer: the decode would size a vector
  // from it (and throw or allocate inside the loop); it never gets that far.
  auto buf = encode(flexloop::test::sized_sample(6, 6));
  for (const std::uint16_t forged :
       {std::uint16_t{0xffff}, std::uint16_t{30000}, std::uint16_t{0}}) {
    buf[32] = static_cast<std::uint8_t>(forged >> 8);
    buf[33] = static_cast<std::uint8_t>(forged & 0xff);
    CHECK(samples.offer(buf.data(), static_cast<int>(buf.size()), 0) == DropReason::kChannelCount);
  }
  CHECK(samples.drops()[DropReason::kChannelCount] == 4);
  CHECK(commands.drops()[DropReason::kChannelCount] == 1);
  CHECK(samples.accepted() == 1);
}

TEST_CASE("NaN or Inf in any float field is dropped as non-finite") {
  MessageInbox<sensor_sample_t> sensors;
  auto s = sample(1, 1, 10);
  s.performance[4] = std::numeric_limits<double>::quiet_NaN();
  CHECK(offer(sensors, s) == DropReason::kNonFinite);
  s = sample(1, 2, 20);
  s.sensors[0] = -std::numeric_limits<double>::infinity();
  CHECK(offer(sensors, s) == DropReason::kNonFinite);
  CHECK(sensors.drops()[DropReason::kNonFinite] == 2);
  CHECK(sensors.accepted() == 0);

  MessageInbox<actuator_command_t> commands(OrderGate(EpochPolicy::kFixed, 1));
  auto c = command(1, 1, 10);
  c.commands[3] = std::numeric_limits<double>::infinity();
  CHECK(offer(commands, c) == DropReason::kNonFinite);

  MessageInbox<loop_stats_t> stats;
  loop_stats_t st{};
  st.rate_hz = std::numeric_limits<double>::quiet_NaN();
  CHECK(offer(stats, st) == DropReason::kNonFinite);
  st.rate_hz = 1000;
  CHECK_FALSE(offer(stats, st).has_value());
}

TEST_CASE("a repeated sequence number is a duplicate, a lower one out of order") {
  MessageInbox<sensor_sample_t> inbox;
  REQUIRE_FALSE(offer(inbox, sample(1, 5, 500)).has_value());
  CHECK(offer(inbox, sample(1, 5, 500)) == DropReason::kDuplicate);
  CHECK(offer(inbox, sample(1, 4, 400)) == DropReason::kOutOfOrder);
  CHECK(offer(inbox, sample(1, 3, 600)) == DropReason::kOutOfOrder);
  CHECK(inbox.drops()[DropReason::kDuplicate] == 1);
  CHECK(inbox.drops()[DropReason::kOutOfOrder] == 2);
  CHECK(inbox.newest().seq == 5);
  CHECK_FALSE(offer(inbox, sample(1, 7, 700)).has_value());  // gaps are fine
  CHECK(inbox.accepted() == 2);
  CHECK(inbox.superseded() == 1);  // seq 5 was never taken before seq 7 replaced it
}

TEST_CASE("a message older than the newest seen, or than the age limit, is stale") {
  MessageInbox<sensor_sample_t> inbox;
  REQUIRE_FALSE(offer(inbox, sample(1, 5, 500)).has_value());
  CHECK(offer(inbox, sample(1, 6, 499)) == DropReason::kStale);  // seq ahead, time behind
  // A straggler of an older plant run, arriving after the restart was followed.
  REQUIRE_FALSE(offer(inbox, sample(2, 0, 800)).has_value());
  CHECK(offer(inbox, sample(1, 9, 700)) == DropReason::kStale);
  CHECK(inbox.drops()[DropReason::kStale] == 2);

  MessageInbox<actuator_command_t> aged(OrderGate(EpochPolicy::kFixed, 3, 1000));
  CHECK(offer(aged, command(3, 1, 0), 1001) == DropReason::kStale);
  CHECK_FALSE(offer(aged, command(3, 2, 500), 1400).has_value());
}

TEST_CASE("a plant restart (new epoch) resynchronises the sample receiver") {
  MessageInbox<sensor_sample_t> inbox;
  REQUIRE_FALSE(offer(inbox, sample(1, 100, 1000)).has_value());
  CHECK_FALSE(offer(inbox, sample(2, 0, 2000)).has_value());  // seq restarts with the epoch
  CHECK(inbox.gate().resyncs() == 1);
  CHECK(inbox.gate().epoch() == 2);
  CHECK(offer(inbox, sample(2, 0, 2000)) == DropReason::kDuplicate);
  CHECK_FALSE(offer(inbox, sample(2, 1, 2100)).has_value());
}

TEST_CASE("the plant accepts only answers to its own epoch, ordered by the sample answered") {
  MessageInbox<actuator_command_t> inbox(OrderGate(EpochPolicy::kFixed, 42));
  CHECK(offer(inbox, command(41, 1, 10)) == DropReason::kStale);  // a previous plant run
  REQUIRE_FALSE(offer(inbox, command(42, 10, 100)).has_value());
  CHECK(offer(inbox, command(42, 10, 110)) == DropReason::kDuplicate);
  CHECK(offer(inbox, command(42, 9, 120)) == DropReason::kOutOfOrder);
  // A restarted controller numbers its own commands from 0 again but answers newer samples.
  auto restarted = command(42, 11, 130);
  restarted.seq = 0;
  CHECK_FALSE(offer(inbox, restarted).has_value());
  inbox.gate().set_epoch(43);  // the plant restarted
  CHECK(offer(inbox, command(42, 12, 140)) == DropReason::kStale);
  CHECK_FALSE(offer(inbox, command(43, 0, 150)).has_value());
  CHECK(inbox.drops().total() == 4);
  CHECK(inbox.accepted() == 3);
}

TEST_CASE("drop reasons have stable names") {
  CHECK(std::string(to_string(DropReason::kDecodeFailure)) == "decode_failure");
  CHECK(std::string(to_string(DropReason::kNonFinite)) == "non_finite");
  CHECK(std::string(to_string(DropReason::kStale)) == "stale");
  CHECK(std::string(to_string(DropReason::kDuplicate)) == "duplicate");
  CHECK(std::string(to_string(DropReason::kOutOfOrder)) == "out_of_order");
  CHECK(std::string(to_string(DropReason::kChannelCount)) == "channel_count");
}
