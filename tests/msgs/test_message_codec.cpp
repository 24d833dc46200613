// SPDX-License-Identifier: BSD-3-Clause
// The LCM messages of doc/design.md §7: encode/decode round trip, and rejection of truncated or
// foreign (wrong-fingerprint) buffers.
#include <catch2/catch.hpp>
#include <cstdint>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/loop_stats_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <vector>

#include "rt/message_validation.hpp"
#include "tests/support/messages.hpp"

namespace {

template <class Msg>
std::vector<std::uint8_t> encode(const Msg& msg) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
  REQUIRE(msg.encode(buf.data(), 0, static_cast<int>(buf.size())) == static_cast<int>(buf.size()));
  return buf;
}

flexloop_msgs::sensor_sample_t sample_message(int sensors = 6, int performance = 6) {
  auto s = flexloop::test::sized_sample(sensors, performance);
  s.t_ns = 123456789012345;
  s.seq = 42;
  s.plant_epoch = -7;
  for (int i = 0; i < sensors; ++i) s.sensors[i] = 1.5 * i - 2.25;
  for (int i = 0; i < performance; ++i) s.performance[i] = 1e-6 * (i + 1);
  return s;
}

}  // namespace

TEST_CASE("sensor sample survives an encode/decode round trip bit for bit") {
  const auto s = sample_message();
  const auto buf = encode(s);
  flexloop_msgs::sensor_sample_t d{};
  REQUIRE(d.decode(buf.data(), 0, static_cast<int>(buf.size())) == static_cast<int>(buf.size()));
  CHECK(d.t_ns == s.t_ns);
  CHECK(d.seq == s.seq);
  CHECK(d.plant_epoch == s.plant_epoch);
  CHECK(d.sensors == s.sensors);
  CHECK(d.performance == s.performance);
}

TEST_CASE("a sample of 64 sensor and 64 performance channels fits one UDP datagram") {
  // LCM's UDP multicast sends a message of up to 65499 bytes minus its 8-byte header in one
  // datagram, but fragments above what fits one Ethernet frame; doc/design.md §7 sets ~1400 bytes.
  // The channel name travels too: FLEXLOOP_SENSOR and its NUL, plus the 8-byte LCM header.
  const auto s = sample_message(64, 64);
  const int payload = s.getEncodedSize();
  CHECK(payload ==
        8 + 3 * 8 + 2 * 2 + 128 * 8 + 8 + 8);  // fingerprint, 3 int64, 2 counts, values, applied
  CHECK(8 + static_cast<int>(sizeof "FLEXLOOP_SENSOR") + payload <= 1400);
}

TEST_CASE("the channel counts sit where the validation reads them before decoding") {
  // rt/message_validation.cpp reads the int16 counts from fixed byte offsets; the generated
  // encoder decides the layout.
  for (const auto& [ns, nz] : {std::pair{3, 5}, std::pair{64, 1}}) {
    const auto buf = encode(sample_message(ns, nz));
    CHECK(flexloop::rt::check_counts(static_cast<flexloop_msgs::sensor_sample_t*>(nullptr),
                                     buf.data(), static_cast<int>(buf.size()), {ns, nz}));
    CHECK_FALSE(flexloop::rt::check_counts(static_cast<flexloop_msgs::sensor_sample_t*>(nullptr),
                                           buf.data(), static_cast<int>(buf.size()), {ns + 1, nz}));
  }
  const auto buf = encode(flexloop::test::sized_command(7));
  CHECK(flexloop::rt::check_counts(static_cast<flexloop_msgs::actuator_command_t*>(nullptr),
                                   buf.data(), static_cast<int>(buf.size()), {7, 0}));
  CHECK(flexloop::rt::has_fingerprint<flexloop_msgs::actuator_command_t>(
      buf.data(), static_cast<int>(buf.size())));
  CHECK_FALSE(flexloop::rt::has_fingerprint<flexloop_msgs::sensor_sample_t>(
      buf.data(), static_cast<int>(buf.size())));
}

TEST_CASE("actuator command and loop statistics survive a round trip") {
  auto a = flexloop::test::sized_command();
  a.t_ns = 99;
  a.seq = 3;
  a.answers_seq = 2;
  a.plant_epoch = 11;
  a.controller_compute_ns = 250;
  for (int i = 0; i < 6; ++i) a.commands[i] = -0.125 * i;
  const auto abuf = encode(a);
  flexloop_msgs::actuator_command_t ad{};
  REQUIRE(ad.decode(abuf.data(), 0, static_cast<int>(abuf.size())) ==
          static_cast<int>(abuf.size()));
  CHECK(ad.answers_seq == 2);
  CHECK(ad.controller_compute_ns == 250);
  CHECK(ad.commands == a.commands);

  flexloop_msgs::loop_stats_t st{};
  st.rate_hz = 10000.0;
  st.cycles = 100000;
  st.deadline_misses = 4;
  for (int i = 0; i < 5; ++i) st.round_trip_ns[i] = 1000 * (i + 1);
  const auto sbuf = encode(st);
  flexloop_msgs::loop_stats_t sd{};
  REQUIRE(sd.decode(sbuf.data(), 0, static_cast<int>(sbuf.size())) ==
          static_cast<int>(sbuf.size()));
  CHECK(sd.rate_hz == 10000.0);
  CHECK(sd.deadline_misses == 4);
  CHECK(sd.round_trip_ns[4] == 5000);
}

TEST_CASE("a truncated buffer is rejected") {
  const auto buf = encode(sample_message());
  flexloop_msgs::sensor_sample_t d{};
  for (std::size_t len :
       {std::size_t{0}, std::size_t{4}, std::size_t{8}, buf.size() / 2, buf.size() - 1}) {
    INFO("length " << len);
    CHECK(d.decode(buf.data(), 0, static_cast<int>(len)) < 0);
  }
}

TEST_CASE("a buffer of another message type (wrong fingerprint) is rejected") {
  flexloop_msgs::actuator_command_t a{};
  const auto abuf = encode(a);
  flexloop_msgs::sensor_sample_t d{};
  CHECK(d.decode(abuf.data(), 0, static_cast<int>(abuf.size())) < 0);

  auto sbuf = encode(sample_message());
  sbuf[0] ^= 0x01;  // corrupt the 8-byte fingerprint
  CHECK(d.decode(sbuf.data(), 0, static_cast<int>(sbuf.size())) < 0);
}
