// SPDX-License-Identifier: BSD-3-Clause
// The real-time loop end to end (online/hil/hil_run.hpp): the metrology scene, plant and
// controller in two processes on the two cores over LCM in a private loopback-only namespace,
// judged only against the baselines measured in the same run, interleaved with it in 5 segments
// (A1 B1 ... A5 B5, online/hil/interleaved_baselines.hpp). Each loop segment is held to
// the baseline segment just before it (hil::BaselineMargins):
//   deadline misses  <= 2 x the bare ping-pong's unanswered share + 1 % of the cycles
//   round trip p99   <= 1.5 x the bare ping-pong's p99 + one bare-timer p99 (the loop has a
//                       plant and a controller step and a publish more than the bare exchange)
// and the median segment must be within both; plus correctness: every cycle ran, no message was
// dropped, the controller answered. Two runs, both with the default settings (hybrid wait, direct
// receive): at 1 kHz for 10 s (2 s, 2000 cycles, per segment), and at the highest rate of 1, 2,
// 5, 10, 20 kHz that the bare baselines themselves can hold, for as long as gives each segment at
// least those 2000 cycles and 1 s (5 s from 2 kHz up). This VM's tails come in bursts (a vCPU
// stalled for milliseconds costs tens of misses at once): the median segment is judged, not the
// worst, and a run outside the margins is repeated once, with its own baselines (a loop that is
// really slower fails both). Needs root for the namespace; without it the case says so and checks
// nothing.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "offline/scene/loop_input.hpp"
#include "online/hil/hil_run.hpp"
#include "tests/support/metrology.hpp"
#include "tests/timing/private_network.hpp"

using namespace flexloop;
using test::in_private_network;

namespace {

constexpr int kSegments = 5;

hil::HilOptions options(double rate_hz, rt::WaitMode wait) {
  hil::HilOptions o;
  o.loop.loop_path = test::metrology_scene_path();
  o.loop.rate_hz = rate_hz;
  o.loop.duration_s = 10;
  o.loop.wait = wait;
  o.loop.realtime = {.cpu = 0, .fifo_priority = 80};
  o.controller_cpu = 1;
  o.segments = kSegments;  // the baselines as long as the loop (the default)
  o.netns = true;
  return o;
}

artefact::LoopArtefact loop(const hil::HilOptions& o);

// The timing margins alone (no CHECK): the median segment against its baseline segment.
bool within_margins(const nlohmann::json& r) {
  return r["baseline_ratios"]["median_segment_within_margins"].get<bool>();
}

// One run, and a second one when the first is outside the margins: this VM's stalls come in
// bursts of seconds, which the baselines and the loop need not both catch, so one run outside
// the margins says little; a slower loop fails both.
nlohmann::json run_judged(const hil::HilOptions& o) {
  nlohmann::json r = hil::run_hil(o, loop(o));
  if (within_margins(r)) return r;
  WARN("outside the margins once (round trip p99 "
       << r["round_trip_ns"]["p99"] << " ns, misses " << r["deadline_misses"]
       << ", segments: " << r["baseline_ratios"]["segments"].dump() << "): running again");
  return hil::run_hil(o, loop(o));
}

void check_against_baselines(const nlohmann::json& r, double rate_hz, double duration_s) {
  const auto& pp = r["baseline"]["pingpong"];
  const auto& timer = r["baseline"]["timer"];
  const double cycles = r["cycles"].get<double>();
  const double misses = r["deadline_misses"].get<double>();
  const double rtt_p99 = r["round_trip_ns"]["p99"].get<double>();
  const double pp_p99 = pp["round_trip_ns"]["p99"].get<double>();
  const double timer_p99 = timer["wakeup_lateness_ns"]["p99"].get<double>();
  const auto& ratios = r["baseline_ratios"];
  WARN(rate_hz << " Hz, wait " << r["wait_mode"] << ", receive " << r["receive_path"] << ": cycles "
               << cycles << ", misses " << misses << ", round trip p50/p99/max "
               << r["round_trip_ns"]["p50"] << "/" << rtt_p99 << "/" << r["round_trip_ns"]["max"]
               << " ns; baseline ping-pong p50/p99 " << pp["round_trip_ns"]["p50"] << "/" << pp_p99
               << " ns, unanswered " << pp["unanswered"] << " of " << pp["sent"] << "; timer p99 "
               << timer_p99 << " ns; per segment: round-trip p99 ratio "
               << ratios["round_trip_p99_ratio"].dump() << ", margin use "
               << ratios["margin_use"].dump() << ", " << ratios["segments_within_margins"] << " of "
               << kSegments << " within the margins");
  // The loop stops once the grid has covered the duration; a stall in its last cycle skips
  // periods (the overrun policy) and can carry the grid past the end by those.
  const double periods = r["periods"].get<double>();
  const double skipped = r["skipped_periods"].get<double>();
  CHECK(periods >= std::round(duration_s * rate_hz));
  CHECK(periods <= std::round(duration_s * rate_hz) + skipped);
  CHECK(cycles + skipped == periods);
  CHECK(r["dropped_messages"]["decode_failure"] == 0);
  CHECK(r["dropped_messages"]["non_finite"] == 0);
  CHECK(r["controller"]["dropped_messages"]["non_finite"] == 0);
  CHECK(r["controller"]["answered"].get<double>() >= cycles - misses);
  // Every segment ran and was compared; the median one within both margins.
  REQUIRE(ratios["segments"].size() == kSegments);
  double segment_periods = 0;
  for (const auto& s : r["segments"]) segment_periods += s["periods"].get<double>();
  CHECK(segment_periods == periods);
  CHECK(ratios["margin_use"]["median"].get<double>() <= 1.0);
  CHECK(ratios["median_segment_within_margins"] == true);
}

// The scene's loop at the options' rate (the artefact `flexloop hil` builds).
artefact::LoopArtefact loop(const hil::HilOptions& o) {
  return scene::load_loop(o.loop.loop_path,
                          {.rate_hz = o.loop.rate_hz, .form = std::nullopt, .duration_s = 0});
}

}  // namespace

TEST_CASE("hil at 1 kHz: misses and round-trip p99 within a margin of the same-run baselines") {
  const hil::HilOptions o = options(1000, rt::WaitMode::kHybrid);
  if (!in_private_network(o)) return;
  check_against_baselines(run_judged(o), 1000, o.loop.duration_s);
}

TEST_CASE(
    "hil at the highest rate the baselines allow: misses and round-trip p99 within a margin "
    "of the same-run baselines") {
  hil::HilOptions o = options(1000, rt::WaitMode::kHybrid);
  if (!in_private_network(o)) return;
  // The rate: the highest whose bare baselines (1 s each, the loop's settings, the report's own
  // baseline code) answer 99 % of the pings within the period and leave half the period free at
  // p99 (ping-pong round trip + timer lateness).
  double rate_hz = 1000;
  for (const double candidate : {20000.0, 10000.0, 5000.0, 2000.0}) {
    hil::HilOptions probe = o;
    probe.baseline_duration_s = 1;
    const nlohmann::json b = hil::run_baselines(probe, candidate);
    const auto& pp = b["pingpong"];
    const double unanswered = pp["unanswered"].get<double>() / pp["sent"].get<double>();
    const double busy_ns = pp["round_trip_ns"]["p99"].get<double>() +
                           b["timer"]["wakeup_lateness_ns"]["p99"].get<double>();
    const double period_ns = 1e9 / candidate;
    WARN(candidate << " Hz baselines: ping-pong unanswered " << 100 * unanswered
                   << " %, p99 round trip + timer lateness " << busy_ns << " ns of a " << period_ns
                   << " ns period");
    if (unanswered <= 0.01 && busy_ns <= 0.5 * period_ns) {
      rate_hz = candidate;
      break;
    }
  }
  o.loop.rate_hz = rate_hz;
  // Each segment's p99 and miss share rest on as many cycles as the 1 kHz run's (2000) at least,
  // and a segment lasts 1 s at least, long against one VM stall (milliseconds).
  o.loop.duration_s = kSegments * std::max(1.0, 2000 / rate_hz);
  check_against_baselines(run_judged(o), rate_hz, o.loop.duration_s);
}

TEST_CASE(
    "hil over iceoryx at 20 kHz: misses and round-trip p99 within a margin of the same-run "
    "iceoryx ping-pong") {
  // Shared memory instead of UDP (rt/loop_transport.hpp), judged against the ping-pong on the
  // same carrier, interleaved as over LCM. 1 s per segment (20 000 cycles); the baselines 0.5 s
  // per segment each (timer, iceoryx ping-pong, and the LCM ping-pong beside it).
  hil::HilOptions o = options(20000, rt::WaitMode::kHybrid);
  o.loop.transport = rt::TransportKind::kIceoryx;
  o.loop.duration_s = kSegments * 1.0;
  o.baseline_duration_s = kSegments * 0.5;
  if (!in_private_network(o)) return;
  const nlohmann::json r = run_judged(o);
  CHECK(r["transport"] == "iceoryx");
  CHECK(r["baseline"]["pingpong"]["transport"] == "iceoryx");
  check_against_baselines(r, 20000, o.loop.duration_s);
}
