// SPDX-License-Identifier: BSD-3-Clause
// Per-step cost of each simulated-hardware effect (issue 6: "each effect's own cost is
// reported"), N = 6 channels, double and float. Inputs cycle through 1024 precomputed random
// vectors (about a third of the actuator commands saturate), so branches and the data path see
// a realistic mix; each result is the ns for one step of all six channels.
//   Piezo / PiezoLagged: gain, limits, saturation flags (+ first-order lag)
//   GainError, Noise (additive Gaussian, per-channel xoshiro256++), Quantiser (16 bit), Delay (3 of
//   at most 8 samples), Floor (order-9 VC-C shaping filter at 1 kHz, 6 channels)
#include <benchmark/benchmark.h>

#include <array>
#include <boost/random/normal_distribution.hpp>
#include <random>
#include <vector>

#include "plant/lti/vibration_criterion.hpp"
#include "plant/runtime/effects/additive_noise.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/gain_error.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/quantiser.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "plant/runtime/effects/xoshiro256.hpp"

using namespace flexloop::plant::runtime::effects;

namespace {

constexpr int kN = 6;
constexpr double kDt = 1e-3;
using P = ChannelParameters<kN>;

template <class Scalar>
const std::vector<ChannelVector<Scalar, kN>>& inputs() {
  static const auto v = [] {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n(0, 40);  // |x| > 50 about a fifth of the time
    std::vector<ChannelVector<Scalar, kN>> s(1024);
    for (auto& x : s)
      for (int c = 0; c < kN; ++c) x(c) = static_cast<Scalar>(n(rng));
    return s;
  }();
  return v;
}

// Runs effect.step(input) once per iteration.
template <class Scalar, class Effect>
void run(benchmark::State& state, Effect effect) {
  const auto& in = inputs<Scalar>();
  std::size_t k = 0;
  for (auto _ : state) {
    auto y = effect.step(in[k++ & 1023]);
    benchmark::DoNotOptimize(y);
  }
}

PiezoActuatorParameters<kN> piezo(double tau) {
  PiezoActuatorParameters<kN> p;
  p.force_min = P::Constant(-50);
  p.force_max = P::Constant(50);
  p.lag_time_constant = P::Constant(tau);
  return p;
}

template <class Scalar>
void BM_Piezo(benchmark::State& s) {
  run<Scalar>(s, PiezoActuator<Scalar, kN>::from_parameters(piezo(0), kDt));
}
template <class Scalar>
void BM_PiezoLagged(benchmark::State& s) {
  run<Scalar>(s, PiezoActuator<Scalar, kN, true>::from_parameters(piezo(2e-4), kDt));
}
template <class Scalar>
void BM_GainError(benchmark::State& s) {
  run<Scalar>(s, GainError<Scalar, kN>::from_parameters(P::Constant(0.01)));
}
template <class Scalar>
void BM_Noise(benchmark::State& s) {
  run<Scalar>(s, AdditiveNoise<Scalar, kN>::from_parameters(P::Constant(0.1), 7));
}
template <class Scalar>
void BM_Quantiser(benchmark::State& s) {
  run<Scalar>(s, Quantiser<Scalar, kN>::from_parameters(16, P::Constant(200)));
}
template <class Scalar>
void BM_Delay(benchmark::State& s) {
  run<Scalar>(s, SampleDelay<Scalar, kN, 8>::from_parameters(3));
}
template <class Scalar>
void BM_Floor(benchmark::State& state) {
  namespace lti = flexloop::plant::lti;
  const auto d = lti::discretise_floor_filter(lti::design_floor_filter(12.5e-6), kDt);
  auto floor = FloorGenerator<Scalar, kN, lti::kFloorFilterOrder>::from_parameters(
      d.sys.A, d.sys.B, d.sys.C, d.sys.D, 11);
  for (auto _ : state) {
    auto a = floor.step();
    benchmark::DoNotOptimize(a);
  }
}

}  // namespace

// One standard normal draw per channel for 18 channels (the floor's 6 and two sensor chains of 6,
// as the default scene draws them each sample), each channel with its own engine: the engine the
// noise effects use against std::mt19937_64 (same-run baseline), both through Boost's scalar
// ziggurat (the noise's transform before the lanes below).
template <class Engine>
void BM_NormalDraws18(benchmark::State& s) {
  std::array<Engine, 18> engines;
  for (std::size_t c = 0; c < engines.size(); ++c) engines[c] = Engine(c + 1);
  boost::random::normal_distribution<double> normal;
  double sum = 0;
  for (auto _ : s)
    for (auto& e : engines) sum += normal(e);
  benchmark::DoNotOptimize(sum);
}
BENCHMARK_TEMPLATE(BM_NormalDraws18, flexloop::plant::runtime::effects::Xoshiro256PlusPlus);
BENCHMARK_TEMPLATE(BM_NormalDraws18, std::mt19937_64);

// The same 18 draws as the effects take them: three 6-channel sources (floor, force sensors,
// accelerometers), each channel's engine in a SIMD lane of the ziggurat (gaussian_noise.hpp);
// against the scalar ziggurat on each engine in turn (the same numbers) and Boost's above.
static void BM_NormalDraws18Lanes(benchmark::State& s) {
  using flexloop::plant::runtime::effects::GaussianNoise;
  auto a = GaussianNoise<double, 6>::from_seed(1), b = GaussianNoise<double, 6>::from_seed(2),
       c = GaussianNoise<double, 6>::from_seed(3);
  for (auto _ : s) {
    auto x = a.sample(), y = b.sample(), z = c.sample();
    benchmark::DoNotOptimize(x);
    benchmark::DoNotOptimize(y);
    benchmark::DoNotOptimize(z);
  }
}
BENCHMARK(BM_NormalDraws18Lanes);
static void BM_NormalDraws18Scalar(benchmark::State& s) {
  namespace fx = flexloop::plant::runtime::effects;
  std::array<fx::Xoshiro256PlusPlus, 18> engines;
  for (std::size_t c = 0; c < engines.size(); ++c) engines[c] = fx::Xoshiro256PlusPlus(c + 1);
  double sum = 0;
  for (auto _ : s)
    for (auto& e : engines) sum += fx::ziggurat::normal(e);
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_NormalDraws18Scalar);

BENCHMARK_TEMPLATE(BM_Piezo, double);
BENCHMARK_TEMPLATE(BM_Piezo, float);
BENCHMARK_TEMPLATE(BM_PiezoLagged, double);
BENCHMARK_TEMPLATE(BM_PiezoLagged, float);
BENCHMARK_TEMPLATE(BM_GainError, double);
BENCHMARK_TEMPLATE(BM_GainError, float);
BENCHMARK_TEMPLATE(BM_Noise, double);
BENCHMARK_TEMPLATE(BM_Noise, float);
BENCHMARK_TEMPLATE(BM_Quantiser, double);
BENCHMARK_TEMPLATE(BM_Quantiser, float);
BENCHMARK_TEMPLATE(BM_Delay, double);
BENCHMARK_TEMPLATE(BM_Delay, float);
BENCHMARK_TEMPLATE(BM_Floor, double);
BENCHMARK_TEMPLATE(BM_Floor, float);
