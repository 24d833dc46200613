// SPDX-License-Identifier: BSD-3-Clause
// What each simulated-hardware effect costs per closed-loop step, and that an absent one costs
// nothing (issue 6): the metrology plant + PI + white floor written by hand (the bare baseline),
// the same through SimulatedHardware with no effect, and with one effect at a time; and the
// default scene's loop with its hardware composed at compile time against chosen at start-up.
//
//   tools/bench --benchmark_filter=Effect
#include <benchmark/benchmark.h>

#include "controller/runtime/pi_controller.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/loop_hardware.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "plant/runtime/effects/sensor_chain.hpp"
#include "plant/runtime/effects/white_floor.hpp"
#include "plant/runtime/simulated_hardware.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
namespace fx = plant::runtime::effects;
using Plant = plant::runtime::DensePlant<double, 12, 12, 12, 6>;  // holds the actuator forces
using Floor = fx::WhiteFloor<double, 6>;
using Pi = controller::runtime::PiController<double, 6>;
using plant::runtime::NoEffect;

namespace {

Plant make_plant() {
  const auto& d = test::metrology().s.plant.sys;
  return Plant::from_matrices(d.A, d.B, d.C, d.D);
}
Floor make_floor() {
  return Floor::from_parameters(1e-3, 1);
}
Pi make_pi() {
  return Pi::from_parameters(test::metrology_pi_parameters());
}

// The bare loop, by hand: floor, plant output with the held command, PI, plant advance.
void BM_EffectNoneByHand(benchmark::State& state) {
  Plant plant = make_plant();
  Floor floor = make_floor();
  Pi pi = make_pi();
  Plant::Input in = Plant::Input::Zero();
  for (auto _ : state) {
    in.head<6>() = floor.step();
    const Plant::Output y = plant.output(in.head<6>());
    in.tail<6>() = pi.step(y.tail<6>());
    plant.advance(in);
    benchmark::DoNotOptimize(in);
  }
}
BENCHMARK(BM_EffectNoneByHand);

template <class Hardware>
void run(benchmark::State& state, Hardware hw) {
  Pi pi = make_pi();
  for (auto _ : state) {
    const auto& r = hw.sample();
    const auto u = pi.step(r.sensors);
    hw.apply(u);
    benchmark::DoNotOptimize(u);
  }
}

template <int N>
fx::SensorParameters<N> sensor(double noise, double range) {
  fx::SensorParameters<N> p;
  p.noise_rms.setConstant(noise);
  p.adc_range.setConstant(range);
  return p;
}

fx::PiezoActuatorParameters<6> piezo(double lag) {
  fx::PiezoActuatorParameters<6> p;
  p.force_min.setConstant(-500);
  p.force_max.setConstant(500);
  p.lag_time_constant.setConstant(lag);
  return p;
}

void BM_EffectNoneComposed(benchmark::State& state) {
  run(state, plant::runtime::SimulatedHardware<Plant, 6, 6, Floor>(make_plant(), make_floor()));
}
BENCHMARK(BM_EffectNoneComposed);

void BM_EffectPiezo(benchmark::State& state) {
  using A = fx::PiezoActuator<double, 6, false>;
  run(state, plant::runtime::SimulatedHardware<Plant, 6, 6, Floor, A>(
                 make_plant(), make_floor(), A::from_parameters(piezo(0), 1e-4)));
}
BENCHMARK(BM_EffectPiezo);

void BM_EffectPiezoLag(benchmark::State& state) {
  using A = fx::PiezoActuator<double, 6, true>;
  run(state, plant::runtime::SimulatedHardware<Plant, 6, 6, Floor, A>(
                 make_plant(), make_floor(), A::from_parameters(piezo(2e-4), 1e-4)));
}
BENCHMARK(BM_EffectPiezoLag);

void BM_EffectForceSensor(benchmark::State& state) {
  using S = fx::SensorChain<double, 6>;
  run(state, plant::runtime::SimulatedHardware<Plant, 6, 6, Floor, NoEffect, S>(
                 make_plant(), make_floor(), {}, S::from_parameters(sensor<6>(2e-3, 200))));
}
BENCHMARK(BM_EffectForceSensor);

void BM_EffectAccelerometer(benchmark::State& state) {
  using S = fx::SensorChain<double, 6>;
  run(state, plant::runtime::SimulatedHardware<Plant, 6, 6, Floor, NoEffect, NoEffect, S>(
                 make_plant(), make_floor(), {}, {}, S::from_parameters(sensor<6>(1e-5, 1))));
}
BENCHMARK(BM_EffectAccelerometer);

void BM_EffectTransportDelay(benchmark::State& state) {
  using D = fx::TransportDelay<double, 6, 6>;
  run(state, plant::runtime::SimulatedHardware<Plant, 6, 6, Floor, NoEffect, NoEffect, NoEffect, D>(
                 make_plant(), make_floor(), {}, {}, {}, D::from_parameters(1)));
}
BENCHMARK(BM_EffectTransportDelay);

}  // namespace

namespace {

// The default scene's loop (VC-C floor, piezos, force sensors, accelerometers, PI), its hardware
// composed at compile time (what `flexloop sim` runs for this listed effect set) and chosen at
// start-up (what every set that online/sim/loop_hardware.hpp does not list runs).
const artefact::LoopArtefact& default_scene() {
  static const artefact::LoopArtefact a = scene::load_loop(test::metrology_scene_path());
  return a;
}

template <class Hardware>
void run_scene(benchmark::State& state, Hardware hw) {
  auto pi = Pi::from_parameters(default_scene().pi);
  for (auto _ : state) {
    const auto& r = hw.sample();
    const auto u = pi.step(r.sensors);
    hw.apply(u);
    benchmark::DoNotOptimize(u);
  }
}

void BM_DefaultSceneComposed(benchmark::State& state) {
  const auto& a = default_scene();
  const auto plant = Plant::from_matrices(a.plant.A, a.plant.B, a.plant.C, a.plant.D);
  sim::with_hardware<6, 6>(a, plant, [&](auto hw) { run_scene(state, std::move(hw)); });
}
BENCHMARK(BM_DefaultSceneComposed);

void BM_DefaultSceneChosen(benchmark::State& state) {
  const auto& a = default_scene();
  const auto plant = Plant::from_matrices(a.plant.A, a.plant.B, a.plant.C, a.plant.D);
  sim::with_chosen_hardware<6, 6>(a, plant, [&](auto hw) { run_scene(state, std::move(hw)); });
}
BENCHMARK(BM_DefaultSceneChosen);

}  // namespace
