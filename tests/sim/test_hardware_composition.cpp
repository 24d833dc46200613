// SPDX-License-Identifier: BSD-3-Clause
// The two ways the runtime composes a loop's simulated hardware (online/sim/loop_hardware.hpp)
// give the same loop: a composition fixed at compile time (every absent effect NoEffect) and the
// one whose slots are chosen at start-up (EffectChoice; an absent transport delay a delay of 0)
// produce the same samples, bit for bit, for effect sets that ComposedEffectSets lists and for
// sets it does not, on compiled and start-up-sized counts. with_hardware picks the first for the
// listed sets on compiled loops and the second otherwise.
#include <catch2/catch.hpp>

#include "controller/runtime/controller_from_artefact.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/closed_loop_run.hpp"
#include "online/sim/loop_hardware.hpp"
#include "plant/runtime/plant_from_artefact.hpp"

using namespace flexloop;
using sim::ActuatorKind;

namespace {

constexpr long kSteps = 3000;

sim::RunSettings settings(const artefact::LoopArtefact& a) {
  return {.steps = kSteps, .dt = a.dt(), .log_every = 1, .chunk_steps = kSteps};
}

/// The loop's PI, compiled (N = 6) or sized at start-up (N = Eigen::Dynamic), run on hw.
template <int N, class Hardware>
sim::RunResult run_pi(const Hardware& hw, const artefact::LoopArtefact& a) {
  return controller::runtime::with_controller<double, N>(
      a, [&](auto pi) { return sim::run_closed_loop(hw, std::move(pi), settings(a), {}); });
}

/// The loop with the hardware composed at compile time for the effect set S.
template <int N, bool Vc, ActuatorKind A, bool Force, bool Acc, bool Transport, class Plant>
sim::RunResult composed(const artefact::LoopArtefact& a, const Plant& plant) {
  constexpr int NZ = N;
  const auto& e = a.effects;
  auto hw = sim::compose_hardware<N, N, N>(
      a, plant, sim::make_floor<N, Vc>(a), sim::make_actuator<N, A>(a),
      sim::make_sensor_chain<N, Force>(e.force_sensor, a.sensors()),
      sim::make_sensor_chain<NZ, Acc>(e.accelerometer, a.performance()),
      sim::make_transport_delay<N, NZ, Transport>(a));
  return run_pi<N>(hw, a);
}

/// The same loop with the slots chosen at start-up.
template <int N, class Plant>
sim::RunResult chosen(const artefact::LoopArtefact& a, const Plant& plant) {
  return sim::with_chosen_hardware<N, N, N>(a, plant, [&](auto hw) { return run_pi<N>(hw, a); });
}

/// The loop as with_hardware runs it.
template <int N, class Plant>
sim::RunResult dispatched(const artefact::LoopArtefact& a, const Plant& plant) {
  return sim::with_hardware<N, N, N>(a, plant, [&](auto hw) { return run_pi<N>(hw, a); });
}

double largest_difference(const sim::RunResult& x, const sim::RunResult& y) {
  REQUIRE(x.log.matrix().rows() == kSteps);
  REQUIRE(x.log.matrix().rows() == y.log.matrix().rows());
  REQUIRE(x.log.matrix().cols() == y.log.matrix().cols());
  return (x.log.matrix() - y.log.matrix()).cwiseAbs().maxCoeff();
}

using Frame = plant::runtime::DensePlant<double, 12, 12, 12, 6>;

artefact::LoopArtefact frame() {
  return scene::load_loop("tools/scenes/metrology_frame.toml");
}

}  // namespace

TEST_CASE("hardware composition: a listed effect set, composed or chosen, gives the same loop",
          "[sim][composition]") {
  // The default scene: VC-C floor, piezos, force sensors, accelerometers (listed).
  const auto a = frame();
  REQUIRE(sim::effect_set(a) == sim::EffectSet{.vc_floor = true,
                                               .actuator = ActuatorKind::kPiezo,
                                               .force_sensor = true,
                                               .accelerometer = true});
  const auto plant = Frame::from_matrices(a.plant.A, a.plant.B, a.plant.C, a.plant.D);
  const auto reference = composed<6, true, ActuatorKind::kPiezo, true, true, false>(a, plant);
  CHECK(reference.rms_performance.minCoeff() > 0);
  CHECK(largest_difference(chosen<6>(a, plant), reference) == 0);
  CHECK(largest_difference(dispatched<6>(a, plant), reference) == 0);
}

TEST_CASE("hardware composition: sets no composition lists run chosen, as they would composed",
          "[sim][composition]") {
  const auto base = frame();
  const auto plant = Frame::from_matrices(base.plant.A, base.plant.B, base.plant.C, base.plant.D);
  SECTION("the default scene with a transport delay of 2 samples") {
    auto a = base;
    a.effects.transport_delay_samples = 2;
    const auto reference = composed<6, true, ActuatorKind::kPiezo, true, true, true>(a, plant);
    CHECK(largest_difference(chosen<6>(a, plant), reference) == 0);
    CHECK(largest_difference(dispatched<6>(a, plant), reference) == 0);
  }
  SECTION("a white floor, lagging piezos, accelerometers and no force sensor") {
    auto a = base;
    a.floor.spectrum = artefact::FloorSpectrum::kWhite;
    a.floor.rms_mps2 = 1e-3;
    a.effects.actuator.lag_s = 2e-4;
    a.effects.force_sensor.present = false;
    const auto reference =
        composed<6, false, ActuatorKind::kLaggedPiezo, false, true, false>(a, plant);
    CHECK(largest_difference(chosen<6>(a, plant), reference) == 0);
    CHECK(largest_difference(dispatched<6>(a, plant), reference) == 0);
  }
  SECTION("the VC floor and no effect") {
    auto a = base;
    a.effects = {};
    const auto reference = composed<6, true, ActuatorKind::kNone, false, false, false>(a, plant);
    CHECK(largest_difference(chosen<6>(a, plant), reference) == 0);
    CHECK(largest_difference(dispatched<6>(a, plant), reference) == 0);
  }
}

TEST_CASE("hardware composition: on start-up-sized counts the chosen slots give the composed loop",
          "[sim][composition]") {
  auto a = frame();
  a.effects.transport_delay_samples = 1;
  const auto plant = plant::runtime::GeneralDensePlant<double>::from_matrices(
      a.plant.A, a.plant.B, a.plant.C, a.plant.D, a.actuators());
  constexpr int kAny = Eigen::Dynamic;
  const auto reference = composed<kAny, true, ActuatorKind::kPiezo, true, true, true>(a, plant);
  CHECK(largest_difference(chosen<kAny>(a, plant), reference) == 0);
  CHECK(largest_difference(dispatched<kAny>(a, plant), reference) == 0);
}
