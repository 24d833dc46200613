// SPDX-License-Identifier: BSD-3-Clause
// The verdict of a real-time run (online/loop/run_verdict.hpp) and hil's status line: which limit
// fails a run and in which words, which exit code each verdict gets, and that the JSON a report
// carries reads back as the same verdict; an LCM log that lost messages fails the plant's run.
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <string>

#include "online/hil/status_line.hpp"
#include "online/loop/plant_loop.hpp"
#include "online/loop/run_verdict.hpp"
#include "rt/event_log_recorder.hpp"
#include "rt/monotonic_time.hpp"

using namespace flexloop::hil;
using namespace flexloop::loop;

namespace {
bool mentions(const RunVerdict& v, const std::string& text) {
  for (const auto& r : v.reasons)
    if (r.find(text) != std::string::npos) return true;
  return false;
}
}  // namespace

TEST_CASE("run verdict: a run within its miss limit passes, one above it fails with the share") {
  RunLimits limits;  // 1 % by default
  CHECK(limits.max_miss_share == 0.01);
  const RunVerdict ok = judge_run(RunEnd::kDuration, 10000, 100, limits);
  CHECK(ok.result == RunVerdict::Result::kPass);
  CHECK(ok.reasons.empty());
  CHECK(exit_code(ok) == 0);
  CHECK_NOTHROW(throw_unless_pass(ok));

  const RunVerdict bad = judge_run(RunEnd::kDuration, 10000, 101, limits);
  CHECK(bad.result == RunVerdict::Result::kFail);
  REQUIRE(bad.reasons.size() == 1);
  CHECK(mentions(bad, "1.01 % of 10000 cycles (101), above the limit of 1 %"));
  CHECK(exit_code(bad) == 3);
  try {
    throw_unless_pass(bad);
    FAIL("no VerdictFailure");
  } catch (const VerdictFailure& f) {
    CHECK(f.code == 3);
    CHECK(f.message.find("verdict fail") == 0);
  }
}

TEST_CASE("run verdict: a loop without a controller is not judged on its misses") {
  RunLimits limits;
  limits.judge_misses = false;
  CHECK(judge_run(RunEnd::kDuration, 1000, 1000, limits).result == RunVerdict::Result::kPass);
  CHECK(verdict_json(judge_run(RunEnd::kDuration, 1000, 1000, limits), RunEnd::kDuration,
                     limits)["max_miss_share"] == "not judged (no controller)");
}

TEST_CASE("run verdict: the overrun policy's stop fails the run and says where it stopped") {
  RunLimits limits;
  limits.max_miss_share = 1.0;  // the share alone would pass
  limits.stop_after_misses = 5;
  const RunVerdict v = judge_run(RunEnd::kMissLimit, 5, 5, limits);
  CHECK(v.result == RunVerdict::Result::kFail);
  CHECK(mentions(v, "overrun policy: stopped at the 5-th deadline miss, after 5 cycles"));
  const nlohmann::json j = verdict_json(v, RunEnd::kMissLimit, limits);
  CHECK(j["ended"] == "overrun policy");
  CHECK(j["stop_after_misses"] == 5);
  CHECK(verdict_json(v, RunEnd::kDuration, RunLimits{})["stop_after_misses"].is_null());
}

TEST_CASE("run verdict: an interrupted run is 'interrupted' (130) whatever else it hit") {
  const RunVerdict v = judge_run(RunEnd::kInterrupted, 1000, 900, RunLimits{});
  CHECK(v.result == RunVerdict::Result::kInterrupted);
  CHECK(mentions(v, "above the limit"));  // still said
  CHECK(exit_code(v) == 130);
  RunVerdict w = v;
  add_failure(w, "the controller process failed: x");
  CHECK(w.result == RunVerdict::Result::kInterrupted);
  CHECK(verdict_message(w).find("interrupted (SIGINT/SIGTERM)") == 0);
}

TEST_CASE("run verdict: a failure found outside the loop fails a passing run") {
  RunVerdict v = judge_run(RunEnd::kDuration, 1000, 0, RunLimits{});
  add_failure(v, "the controller process failed: it ended at start (exit code 1)");
  CHECK(v.result == RunVerdict::Result::kFail);
  CHECK(exit_code(v) == 3);
}

TEST_CASE("run verdict: the report's JSON reads back as the same verdict") {
  for (const RunEnd end :
       {RunEnd::kDuration, RunEnd::kInterrupted, RunEnd::kMissLimit, RunEnd::kDivergence}) {
    RunLimits limits;
    limits.stop_after_misses = 7;
    const RunVerdict v = judge_run(end, 100, 7, limits);
    const RunVerdict back = verdict_from_json(verdict_json(v, end, limits));
    CHECK(back.result == v.result);
    CHECK(back.reasons == v.reasons);
  }
  CHECK(judge_run(RunEnd::kDivergence, 10, 0, RunLimits{}).result == RunVerdict::Result::kFail);
  CHECK(judge_run(RunEnd::kDuration, 0, 0, RunLimits{}).result == RunVerdict::Result::kPass);
}

TEST_CASE("hil status line: the figures of the last second in the user's units") {
  const std::string line = StatusLine::format(10000, 40000, 100000, 12, 0, 41234, true);
  CHECK(line ==
        "hil 10 kHz: 4 / 10 s, 40000 cycles, 12 misses (0.030 %), round trip p99 41.2 us, safe 0");
  // No controller process: unanswered samples are expected, not misses.
  CHECK(StatusLine::format(10000, 40000, 100000, 40000, 40000, 0, false) ==
        "hil 10 kHz, no controller process: 4 / 10 s, 40000 cycles, 40000 unanswered, round "
        "trip p99 0.0 us, safe 40000");
  SharedLoopStatus status;
  StatusLine quiet(*status.get(), 1000, false, true);
  CHECK_FALSE(quiet.enabled());
}

TEST_CASE("run verdict: an LCM log whose ring overflowed fails the run with what it lost") {
  // A forced overflow: a ring of two messages fed 20 000 in a tight loop while its writer sleeps
  // between batches (rt/event_log_recorder.hpp). What the ring could not keep is counted by the
  // recorder, and the plant's verdict fails on it, naming the log and the count: never silent.
  const std::string path =
      (std::filesystem::temp_directory_path() / "flexloop_test_overflow.lcmlog").string();
  flexloop::rt::EventLogRecorder recorder(path, 16, 2);
  const int channel = recorder.channel("FLEXLOOP_SENSOR");
  const std::uint8_t payload[16] = {};
  for (int i = 0; i < 20000; ++i)
    recorder.record(channel, payload, sizeof payload, flexloop::rt::monotonic_now_ns());
  PlantLoopResult r;
  r.cycles = 20000;
  r.lcm_log.error = recorder.finish();
  r.lcm_log.recorded = recorder.recorded();
  r.lcm_log.dropped = recorder.dropped();
  std::filesystem::remove(path);
  CHECK(r.lcm_log.error.empty());
  CHECK(r.lcm_log.recorded + r.lcm_log.dropped == 20000);
  REQUIRE(r.lcm_log.dropped > 0);
  LoopOptions o;
  o.lcm_log = path;
  const RunVerdict v = plant_verdict(r, o);
  CHECK(v.result == RunVerdict::Result::kFail);
  CHECK(mentions(v, "the LCM log " + path + " lost " + std::to_string(r.lcm_log.dropped) +
                        " of 20000 messages"));
  CHECK(exit_code(v) == 3);

  r.lcm_log = {20000, 0, ""};  // the same run with a ring that kept everything passes
  CHECK(plant_verdict(r, o).result == RunVerdict::Result::kPass);
}
