// SPDX-License-Identifier: BSD-3-Clause
// Bad input on both ends of the loop (doc/design.md §7, §9): a message that fails to decode,
// carries NaN or Inf, is stale (another plant run, or longer than a period in transit) or out of
// order is dropped and counted, and never applied -- the plant holds its command (and counts the
// deadline miss), the controller answers nothing.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "tests/hil/station_fixture.hpp"

using namespace flexloop;
using namespace flexloop::test;
using loop::CommandSource;

namespace {

// Runs 100 good cycles, then lets the plant receive `bad` (made from the good answer to the
// newest sample) instead of that answer; checks the drop reason and that nothing was applied.
template <class Spoil>
void check_plant_drops(rt::DropReason expected, Spoil spoil) {
  StationPair pair;
  for (int k = 0; k < 100; ++k) pair.cycle();
  const std::int64_t due = pair.k * kPeriod;
  REQUIRE(pair.plant.settle(due) == CommandSource::kAnswer);
  const auto& s = pair.plant.sample(due);
  REQUIRE_FALSE(deliver(pair.controller.samples(), s, due + kTransit).has_value());
  auto cmd = pair.controller.answer(*pair.controller.samples().take());
  cmd.t_ns = due + kAnswerAfter;
  const ChannelVector after = pair.plant.command();
  std::int64_t received = due + kAnswerAfter + kTransit;
  const auto why = spoil(pair, cmd, received);
  REQUIRE(why.has_value());
  CHECK(*why == expected);
  CHECK(pair.plant.commands().drops()[expected] >= 1);
  CHECK_FALSE(pair.plant.answered());
  ++pair.k;
  CHECK(pair.plant.settle(pair.k * kPeriod) == CommandSource::kHeld);
  CHECK(pair.plant.command() == after);
  CHECK(pair.plant.deadline_misses() == 1);
}

}  // namespace

TEST_CASE("hil plant: an answer that fails to decode is dropped, counted, not applied") {
  check_plant_drops(rt::DropReason::kDecodeFailure,
                    [](StationPair& p, const flexloop_msgs::actuator_command_t& c, std::int64_t t) {
                      std::vector<std::uint8_t> buf(static_cast<std::size_t>(c.getEncodedSize()));
                      c.encode(buf.data(), 0, static_cast<int>(buf.size()));
                      buf[3] ^= 0xFF;  // the type fingerprint
                      return p.plant.commands().offer(buf.data(), static_cast<int>(buf.size()), t);
                    });
  check_plant_drops(rt::DropReason::kDecodeFailure,
                    [](StationPair& p, const flexloop_msgs::actuator_command_t& c, std::int64_t t) {
                      std::vector<std::uint8_t> buf(static_cast<std::size_t>(c.getEncodedSize()));
                      c.encode(buf.data(), 0, static_cast<int>(buf.size()));
                      return p.plant.commands().offer(buf.data(), 20, t);  // truncated
                    });
}

TEST_CASE("hil plant: an answer carrying NaN or Inf is dropped, counted, not applied") {
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    check_plant_drops(rt::DropReason::kNonFinite,
                      [bad](StationPair& p, flexloop_msgs::actuator_command_t c, std::int64_t t) {
                        c.commands[2] = bad;
                        return deliver(p.plant.commands(), c, t);
                      });
  }
}

TEST_CASE("hil plant: a stale answer (other plant run, or a period in transit) is dropped") {
  check_plant_drops(rt::DropReason::kStale,
                    [](StationPair& p, flexloop_msgs::actuator_command_t c, std::int64_t t) {
                      c.plant_epoch += 1;  // answers another plant run
                      return deliver(p.plant.commands(), c, t);
                    });
  check_plant_drops(rt::DropReason::kStale,
                    [](StationPair& p, const flexloop_msgs::actuator_command_t& c, std::int64_t) {
                      return deliver(p.plant.commands(), c, c.t_ns + kPeriod + 1);
                    });
}

TEST_CASE("hil plant: an out-of-order or repeated answer is dropped, counted, not applied") {
  check_plant_drops(rt::DropReason::kOutOfOrder,
                    [](StationPair& p, flexloop_msgs::actuator_command_t c, std::int64_t t) {
                      c.answers_seq -= 2;  // answers an older sample than the newest taken
                      return deliver(p.plant.commands(), c, t);
                    });
  check_plant_drops(rt::DropReason::kDuplicate,
                    [](StationPair& p, flexloop_msgs::actuator_command_t c, std::int64_t t) {
                      c.answers_seq -= 1;  // the answer already applied, again
                      return deliver(p.plant.commands(), c, t);
                    });
}

TEST_CASE("hil controller: bad sensor messages are dropped, counted and never answered") {
  StationPair pair;
  for (int k = 0; k < 50; ++k) pair.cycle();
  auto& inbox = pair.controller.samples();
  auto s = pair.plant.last_sample();
  const std::int64_t now = pair.k * kPeriod;
  s.seq += 1;
  s.t_ns = now;
  auto nan = s;
  nan.sensors[0] = std::numeric_limits<double>::quiet_NaN();
  CHECK(deliver(inbox, nan, now) == rt::DropReason::kNonFinite);
  auto inf = s;
  inf.performance[5] = -std::numeric_limits<double>::infinity();
  CHECK(deliver(inbox, inf, now) == rt::DropReason::kNonFinite);
  auto old = s;
  old.seq -= 3;
  CHECK(deliver(inbox, old, now) == rt::DropReason::kOutOfOrder);
  auto back_in_time = s;
  back_in_time.t_ns = 0;
  CHECK(deliver(inbox, back_in_time, now) == rt::DropReason::kStale);
  std::uint8_t junk[7] = {1, 2, 3, 4, 5, 6, 7};
  CHECK(inbox.offer(junk, sizeof junk, now) == rt::DropReason::kDecodeFailure);
  CHECK_FALSE(inbox.has_fresh());  // nothing to answer
  CHECK(inbox.drops().total() == 5);
  const auto answered = pair.controller.answered();
  REQUIRE_FALSE(deliver(inbox, s, now).has_value());  // the good one is answered
  pair.controller.answer(*inbox.take());
  CHECK(pair.controller.answered() == answered + 1);
}
