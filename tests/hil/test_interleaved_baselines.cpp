// SPDX-License-Identifier: BSD-3-Clause
// The interleaved baselines' arithmetic (online/hil/interleaved_baselines.hpp), on figures made
// up by hand: each loop segment against the baseline segment before it, the margins, the median
// and spread, and the neighbouring LCM port the baselines use. The measurement itself runs in
// tests/timing.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "online/hil/interleaved_baselines.hpp"

using namespace flexloop::hil;

namespace {

nlohmann::json loop_segment(std::int64_t cycles, std::int64_t misses, std::int64_t p99_ns) {
  return {{"periods", cycles},
          {"cycles", cycles},
          {"deadline_misses", misses},
          {"answers", cycles - misses},
          {"round_trip_p99_ns", p99_ns}};
}

}  // namespace

TEST_CASE("interleaved baselines: each loop segment is judged against the baseline before it") {
  // Baseline segment k: 10000 pings, p99 20 us, timer p99 10 us; the second one saw a burst.
  const std::vector<BaselineSegment> baseline = {{.pings = 10000,
                                                  .unanswered = 0,
                                                  .timer_cycles = 10000,
                                                  .pingpong_p99_ns = 20000,
                                                  .timer_p99_ns = 10000},
                                                 {.pings = 10000,
                                                  .unanswered = 500,
                                                  .timer_cycles = 10000,
                                                  .pingpong_p99_ns = 80000,
                                                  .timer_p99_ns = 40000},
                                                 {.pings = 10000,
                                                  .unanswered = 0,
                                                  .timer_cycles = 10000,
                                                  .pingpong_p99_ns = 20000,
                                                  .timer_p99_ns = 10000}};
  // Loop: 30 us (ratio 1.5, allowed 40 us), 150 us in the burst (allowed 160 us, misses 8 % of an
  // allowed 2 x 5 % + 1 % = 11 %), then 50 us (ratio 2.5, over the allowed 40 us).
  const nlohmann::json loop = {loop_segment(10000, 50, 30000), loop_segment(10000, 800, 150000),
                               loop_segment(10000, 0, 50000)};
  const nlohmann::json c = compare_segments(baseline, loop);
  REQUIRE(c["segments"].size() == 3);
  CHECK(c["segments"][0]["round_trip_p99_ratio"].get<double>() == Approx(1.5));
  CHECK(c["segments"][0]["margin_use"].get<double>() == Approx(0.75));  // 30 of 40 us
  CHECK(c["segments"][0]["within_margins"] == true);
  CHECK(c["segments"][1]["unanswered_share"].get<double>() == Approx(0.05));
  CHECK(c["segments"][1]["miss_share"].get<double>() == Approx(0.08));
  CHECK(c["segments"][1]["margin_use"].get<double>() == Approx(150.0 / 160.0));
  CHECK(c["segments"][1]["within_margins"] == true);
  CHECK(c["segments"][2]["margin_use"].get<double>() == Approx(1.25));  // 50 of 40 us
  CHECK(c["segments"][2]["within_margins"] == false);
  CHECK(c["segments_within_margins"] == 2);
  CHECK(c["round_trip_p99_ratio"]["median"].get<double>() == Approx(1.875));  // 1.5, 1.875, 2.5
  CHECK(c["round_trip_p99_ratio"]["min"].get<double>() == Approx(1.5));
  CHECK(c["round_trip_p99_ratio"]["max"].get<double>() == Approx(2.5));
  CHECK(c["miss_share_minus_unanswered"]["median"].get<double>() == Approx(0.005));
  CHECK(c["margin_use"]["median"].get<double>() == Approx(150.0 / 160.0));
  CHECK(c["median_segment_within_margins"] == true);
  // The same loop against one baseline taken in the quiet phase only would fail its burst.
  const nlohmann::json quiet = compare_segments({baseline[0], baseline[0], baseline[0]}, loop);
  CHECK(quiet["segments"][1]["within_margins"] == false);
}

TEST_CASE("interleaved baselines: only the segments both sides have are paired") {
  const std::vector<BaselineSegment> baseline = {{.pings = 1000,
                                                  .unanswered = 0,
                                                  .timer_cycles = 1000,
                                                  .pingpong_p99_ns = 20000,
                                                  .timer_p99_ns = 10000}};
  const nlohmann::json c =
      compare_segments(baseline, {loop_segment(1000, 0, 20000), loop_segment(1000, 0, 20000)});
  CHECK(c["segments"].size() == 1);
  CHECK(compare_segments({}, nlohmann::json::array())["median_segment_within_margins"] == false);
}

TEST_CASE("interleaved baselines: the ping-pong runs on the loop's URL with the next port") {
  CHECK(neighbour_port_url("udpm://239.255.76.67:7667?ttl=0") == "udpm://239.255.76.67:7668?ttl=0");
  CHECK(neighbour_port_url("udpm://239.255.76.67:7000") == "udpm://239.255.76.67:7001");
  CHECK(neighbour_port_url("udpm://239.255.76.67?ttl=0") == "udpm://239.255.76.67:7668?ttl=0");
  CHECK(neighbour_port_url("udpm://239.255.76.67") == "udpm://239.255.76.67:7668");
  CHECK_THROWS_AS(neighbour_port_url("file:///tmp/x.lcm"), std::runtime_error);
  CHECK_THROWS_AS(neighbour_port_url("udpm://239.255.76.67:port?ttl=0"), std::runtime_error);
  CHECK_THROWS_AS(neighbour_port_url("udpm://239.255.76.67:65535"), std::runtime_error);
}
