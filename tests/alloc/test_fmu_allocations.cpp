// SPDX-License-Identifier: BSD-3-Clause
// No allocation inside a step of a controller FMU (issue 33), on flexloop's side or in the
// project's fixture FMUs (tools/fmu/pi_force_feedback, tools/fmu/state_space_controller):
// fmi2SetReal, fmi2DoStep and fmi2GetReal over preallocated value references and buffers, 10^4
// steps after a warm-up, counted by rt/counting_malloc. (A user's FMU may allocate in its own
// code; this counts what we do.)
#include <catch2/catch.hpp>
#include <cmath>

#include "controller/fmu/fmu_controller.hpp"
#include "offline/scene/loop_input.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/metrology.hpp"

namespace {

// Steps `c` (six sensors) 10^4 times after a warm-up: no allocation, a finite answer, no failure.
void check_steps_allocate_nothing(flexloop::controller::fmu::FmuController& c) {
  Eigen::Matrix<double, 6, 1> y = Eigen::Matrix<double, 6, 1>::LinSpaced(-1, 1);
  double sum = 0;
  const auto run = [&](long steps) {
    for (long k = 0; k < steps; ++k) {
      y(k % 6) = 1e-3 * static_cast<double>(k % 7);
      sum += c.step(y)(0);
    }
  };
  run(100);  // warm-up
  const std::uint64_t before = flexloop::test::allocation_count();
  run(10000);
  const std::uint64_t during = flexloop::test::allocation_count() - before;
  CHECK(during == 0);
  CHECK(std::isfinite(sum));
  CHECK(c.failure().empty());
}

}  // namespace

TEST_CASE("A controller FMU's step allocates nothing", "[fmu][alloc]") {
  auto c = flexloop::controller::fmu::FmuController::from_settings(flexloop::test::pi_fmu_settings(
      flexloop::test::metrology_pi_parameters(), flexloop::test::pi_fmu_path()));
  check_steps_allocate_nothing(c);
}

TEST_CASE("The state-space fixture FMU's step allocates nothing", "[fmu][alloc]") {
  // The shipped LQG's discrete design (12 states, 6 channels, D22 = I) as the fixture runs it.
  const auto a = flexloop::scene::load_loop("tools/scenes/metrology_frame_lqg.toml");
  auto c = flexloop::controller::fmu::FmuController::from_settings(
      flexloop::test::state_space_fmu_settings(a.state_space,
                                               flexloop::test::state_space_fmu_path()));
  check_steps_allocate_nothing(c);
}
