// SPDX-License-Identifier: BSD-3-Clause
// A controller FMU's statuses as FMI 2.0 defines them (controller/fmu/fmu_controller.hpp), its
// log without bookkeeping in the step (controller/fmu/fmu_log_ring.hpp), and the first real-time
// cycle of the controller process (online/loop/controller_station.hpp). The fixture PI
// (tools/fmu/pi_force_feedback) answers step N with the status its parameters ask
// (tools/fmu/fixture_fmu.h), aborts the process on a call FMI 2.0 does not allow after it, and
// counts its fmi2Reset and fmi2SetupExperiment calls in two outputs.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <string>

#include "controller/fmu/fmu_controller.hpp"
#include "controller/fmu/fmu_log_ring.hpp"
#include "online/loop/controller_station.hpp"
#include "rt/thread_allocations.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/metrology.hpp"

namespace {

using flexloop::controller::fmu::FmuController;
using Sensors = Eigen::Matrix<double, 6, 1>;

constexpr int kWarning = 1, kDiscard = 2, kPending = 5;

flexloop::controller::fmu::FmuControllerSettings pi_settings() {
  return flexloop::test::pi_fmu_settings(flexloop::test::metrology_pi_parameters(),
                                         flexloop::test::pi_fmu_path());
}

// The fixture PI answering fmi2DoStep number `at` (from 0) with `status`.
FmuController pi_answering(int status, long at) {
  auto s = pi_settings();
  s.parameters.emplace_back("step_status", status);
  s.parameters.emplace_back("status_at_step", static_cast<double>(at));
  return FmuController::from_settings(s);
}

// The sensors of sample k: a slow sine per channel (any measurement the PI answers non-zero).
Sensors sensors(long k) {
  Sensors y;
  for (int i = 0; i < 6; ++i) y(i) = 1e-3 * std::sin(0.01 * static_cast<double>(k) + i);
  return y;
}

}  // namespace

TEST_CASE("fmi2Discard at step N ends the FMU's run there: named, asked, the safe command after",
          "[fmu]") {
  constexpr long kN = 37;
  const double dt = flexloop::test::metrology_pi_parameters().dt;
  FmuController reference = FmuController::from_settings(pi_settings());
  FmuController c = pi_answering(kDiscard, kN);
  for (long k = 0; k < kN; ++k) REQUIRE(c.step(sensors(k)) == reference.step(sensors(k)));
  CHECK(reference.step(sensors(kN)).cwiseAbs().maxCoeff() > 0);
  CHECK(c.step(sensors(kN)).isZero(0));
  CHECK(c.step(sensors(kN + 1)).isZero(0));  // no fmi2DoStep after it (the fixture would abort)
  const flexloop::controller::runtime::ControllerReport r = c.report();
  // The fixture says it wants to terminate and that steps 0 .. N-1 completed: N dt.
  char expected[200];
  std::snprintf(expected, sizeof expected,
                "fmi2DoStep returned fmi2Discard at sample %ld (t = %.9g s); fmi2Terminated: "
                "true, fmi2LastSuccessfulTime: %.9g s",
                kN, static_cast<double>(kN) * dt, static_cast<double>(kN) * dt);
  CHECK(r.failure == expected);
  CHECK_FALSE(r.refused);  // a run the FMU could not complete, not a refusal of its input
  // fmi2Reset is allowed after fmi2Discard: the FMU starts from rest again.
  c.reset();
  FmuController fresh = pi_answering(kDiscard, kN);
  CHECK(c.step(sensors(0)) == fresh.step(sensors(0)));
}

TEST_CASE("fmi2Pending at step N ends the FMU's run there and nothing but fmi2FreeInstance follows",
          "[fmu]") {
  constexpr long kN = 5;
  FmuController c = pi_answering(kPending, kN);
  for (long k = 0; k < kN; ++k) c.step(sensors(k));
  CHECK(c.step(sensors(kN)).isZero(0));
  c.reset();  // no fmi2Reset while the step is pending (the fixture would abort)
  CHECK(c.step(sensors(kN + 1)).isZero(0));
  const auto r = c.report();
  CHECK_THAT(r.failure, Catch::StartsWith("fmi2DoStep returned fmi2Pending at sample 5 (t = "));
  CHECK_THAT(r.failure, Catch::Contains("asynchronous"));
  CHECK_FALSE(r.refused);
}

TEST_CASE("fmi2Warning is counted, its first message kept, and the run goes on unchanged",
          "[fmu]") {
  constexpr long kN = 12;
  FmuController reference = FmuController::from_settings(pi_settings());
  FmuController c = pi_answering(kWarning, kN);
  const std::uint64_t before = flexloop::rt::thread_allocations();
  for (long k = 0; k < 100; ++k) REQUIRE(c.step(sensors(k)) == reference.step(sensors(k)));
  // The warning's message went into the ring, formatted in the step: nothing allocated.
  CHECK(flexloop::rt::thread_allocations() - before == 0);
  const auto r = c.report();
  CHECK(r.failure.empty());
  CHECK(r.warnings == 1);
  CHECK(r.first_warning ==
        "fmi2DoStep returned fmi2Warning at sample 12: step 12 warned as its parameters asked");
  REQUIRE(r.messages.size() == 1);
  CHECK(r.messages[0] == "FMU " + flexloop::test::pi_fmu_path() +
                             " (pi_force_feedback, warning, logStatusWarning): step 12 warned as "
                             "its parameters asked");
  CHECK(r.messages_lost == 0);
  CHECK(c.report().messages.empty());  // taken once
}

namespace {

void log_into(flexloop::controller::fmu::FmuLogRing& ring, fmi2Status status, const char* format,
              ...) {
  std::va_list args;
  va_start(args, format);
  ring.record("instance", status, "category", format, args);
  va_end(args);
}

}  // namespace

TEST_CASE("The FMU's log ring keeps its slots' worth, counts what overflowed, and cuts long text",
          "[fmu]") {
  using flexloop::controller::fmu::FmuLogRing;
  FmuLogRing ring("x.fmu");
  const long n = static_cast<long>(FmuLogRing::kSlots) + 6;
  const std::uint64_t before = flexloop::rt::thread_allocations();
  for (long i = 0; i < n; ++i) log_into(ring, i == 66 ? fmi2Warning : fmi2OK, "message %ld", i);
  CHECK(flexloop::rt::thread_allocations() - before == 0);
  const auto taken = ring.take();
  REQUIRE(taken.size() == FmuLogRing::kSlots);
  CHECK(taken.front() == "FMU x.fmu (instance, ok, category): message 0");
  CHECK(taken.back() == "FMU x.fmu (instance, ok, category): message 63");
  CHECK(ring.lost() == 6);
  CHECK(ring.first_warning() == "message 66");  // kept apart, although the ring was full
  const std::string long_text(1000, 'a');
  log_into(ring, fmi2OK, "%s", long_text.c_str());
  const auto again = ring.take();
  REQUIRE(again.size() == 1);
  CHECK(again[0].size() ==
        std::string("FMU x.fmu (instance, ok, category): ").size() + FmuLogRing::kSlotChars - 1);
}

TEST_CASE("The first real-time cycle steps the FMU as initialised, and a plant restart resets it",
          "[fmu]") {
  auto s = pi_settings();
  s.outputs.push_back("reset_calls");
  s.outputs.push_back("setup_calls");
  flexloop::loop::ControllerStation<FmuController> station(FmuController::from_settings(s), 5);
  flexloop_msgs::sensor_sample_t sample{};
  sample.n_sensors = 6;
  sample.sensors.assign(6, 1e-3);
  sample.applied_scale = 1.0;
  const auto answer = [&](std::int64_t epoch, std::int64_t seq) {
    sample.plant_epoch = epoch;
    sample.seq = seq;
    sample.applied_seq = seq - 1;
    const auto& cmd = station.answer(sample);
    return std::pair{cmd.commands[6], cmd.commands[7]};  // reset_calls, setup_calls
  };
  // The first cycle: the instance as from_settings initialised it (one fmi2SetupExperiment).
  CHECK(answer(1, 1) == std::pair{0.0, 1.0});
  CHECK(answer(1, 2) == std::pair{0.0, 1.0});
  // A new plant epoch: a genuine restart, fmi2Reset and initialisation again.
  CHECK(answer(2, 1) == std::pair{1.0, 2.0});
  CHECK(station.report().failure.empty());
}
