// SPDX-License-Identifier: BSD-3-Clause
// No allocation inside an effect's step (doc/design.md §6): after start-up, 10^5 steps of every
// simulated-hardware effect (piezo actuator with and without lag, gain error, sensor noise, ADC,
// delay, floor generator), N = 6, double and float, counted by rt/counting_malloc.
#include <catch2/catch.hpp>

#include "plant/lti/vibration_criterion.hpp"
#include "plant/runtime/effects/additive_noise.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/gain_error.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/quantiser.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "tests/support/allocation_counter.hpp"

using namespace flexloop;
using namespace flexloop::plant::runtime::effects;

namespace {

template <class Scalar>
std::uint64_t effect_step_allocations() {
  constexpr int kN = 6;
  using P = ChannelParameters<kN>;
  PiezoActuatorParameters<kN> piezo;
  piezo.force_min = P::Constant(-50);
  piezo.force_max = P::Constant(50);
  auto bare = PiezoActuator<Scalar, kN>::from_parameters(piezo, 1e-3);
  piezo.lag_time_constant = P::Constant(2e-4);
  auto lagged = PiezoActuator<Scalar, kN, true>::from_parameters(piezo, 1e-3);
  const auto gain = GainError<Scalar, kN>::from_parameters(P::Constant(0.01));
  auto noise = AdditiveNoise<Scalar, kN>::from_parameters(P::Constant(0.1), 3);
  const auto adc = Quantiser<Scalar, kN>::from_parameters(16, P::Constant(200));
  auto delay = SampleDelay<Scalar, kN, 8>::from_parameters(3);
  const auto d =
      plant::lti::discretise_floor_filter(plant::lti::design_floor_filter(12.5e-6), 1e-3);
  auto floor = FloorGenerator<Scalar, kN, plant::lti::kFloorFilterOrder>::from_parameters(
      d.sys.A, d.sys.B, d.sys.C, d.sys.D, 4);

  ChannelVector<Scalar, kN> x = ChannelVector<Scalar, kN>::Constant(Scalar(1));
  const std::uint64_t before = test::allocation_count();
  for (int k = 0; k < 100000; ++k) {
    const auto a = floor.step();
    const auto f = lagged.step(bare.step(x + Scalar(1e5) * a));
    x = delay.step(adc.step(noise.step(gain.step(f)))) * Scalar(0.5);
  }
  const std::uint64_t after = test::allocation_count();
  REQUIRE(x.allFinite());
  return after - before;
}

}  // namespace

TEST_CASE("allocation: 10^5 steps of every effect allocate nothing (double and float, N = 6)",
          "[alloc]") {
  CHECK(effect_step_allocations<double>() == 0);
  CHECK(effect_step_allocations<float>() == 0);
}
