// SPDX-License-Identifier: BSD-3-Clause
// The controller process's watch on a controller it cannot see into (online/loop/
// real_time_promises.hpp): the counting allocator sees the allocations a controller FMU makes in
// its step (the fixture's allocations_per_step), none for the fixture as shipped, and the report
// says kept, BROKEN or not counted from the counts and the answer times.
#include <catch2/catch.hpp>
#include <cstdint>

#include "controller/fmu/fmu_controller.hpp"
#include "online/loop/real_time_promises.hpp"
#include "rt/thread_allocations.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/metrology.hpp"

namespace {

// Allocations counted on this thread over `steps` steps of the fixture PI FMU after a warm-up,
// the fixture making `per_step` malloc/free pairs in each fmi2DoStep.
std::uint64_t allocations_in_steps(int per_step, long steps) {
  auto settings = flexloop::test::pi_fmu_settings(flexloop::test::metrology_pi_parameters(),
                                                  flexloop::test::pi_fmu_path());
  settings.parameters.emplace_back("allocations_per_step", per_step);
  auto c = flexloop::controller::fmu::FmuController::from_settings(settings);
  Eigen::Matrix<double, 6, 1> y = Eigen::Matrix<double, 6, 1>::Constant(1e-3);
  for (int k = 0; k < 10; ++k) c.step(y);  // warm-up
  const std::uint64_t before = flexloop::rt::thread_allocations();
  for (long k = 0; k < steps; ++k) c.step(y);
  const std::uint64_t during = flexloop::rt::thread_allocations() - before;
  CHECK(c.failure().empty());
  return during;
}

}  // namespace

TEST_CASE("The counting allocator sees a controller FMU's allocations in its steps",
          "[fmu][alloc]") {
#ifdef FLEXLOOP_COUNTS_ALLOCATIONS
  REQUIRE(flexloop::rt::allocations_counted());
  CHECK(allocations_in_steps(0, 1000) == 0);
  CHECK(allocations_in_steps(3, 1000) == 3000);
#else
  // A sanitizer build: its runtime owns malloc, nothing is counted, and the report says so.
  CHECK_FALSE(flexloop::rt::allocations_counted());
  CHECK(allocations_in_steps(3, 10) == 0);
#endif
}

TEST_CASE("The real-time promises are kept, BROKEN or not counted as the watch saw them", "[fmu]") {
  using flexloop::loop::AnswerWatch;
  using flexloop::loop::real_time_promises_json;
  AnswerWatch w;
  w.allocations_counted = true;
  w.answered = 10000;
  w.period_ns = 100'000;
  w.compute.p99 = 400;
  w.compute.max = 2'000'000;  // a millisecond tail: shown, not judged
  auto p = real_time_promises_json(w);
  CHECK(p["no_allocation"]["kept"] == true);
  CHECK(p["step_time"]["kept"] == true);
  CHECK(p["step_time"]["p99_share_of_period"] == Approx(0.004));
  CHECK(p["no_failed_call"]["kept"] == true);
  CHECK(p["no_lock_or_system_call"]["kept"].is_null());
  CHECK(p["summary"].get<std::string>().find("no allocation kept (0 allocations in 0 of 10000") !=
        std::string::npos);

  w.allocations = 30000;
  w.answers_allocating = 10000;
  w.compute.p99 = 15'000;  // 15 % of the period
  w.controller_failure = "fmi2DoStep returned fmi2Error at sample 12 (t = 0.0012 s)";
  p = real_time_promises_json(w);
  CHECK(p["no_allocation"]["kept"] == false);
  CHECK(p["step_time"]["kept"] == false);
  CHECK(p["no_failed_call"]["kept"] == false);
  CHECK(p["no_failed_call"]["failure"] == w.controller_failure);
  CHECK(p["summary"].get<std::string>().find("no allocation BROKEN (30000 allocations") !=
        std::string::npos);

  w.allocations_counted = false;
  p = real_time_promises_json(w);
  CHECK(p["no_allocation"]["kept"].is_null());
  CHECK(p["summary"].get<std::string>().find("no allocation not counted") != std::string::npos);
}
