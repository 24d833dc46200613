// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Start-up: from a loop artefact's floor and effects (artefact/loop_artefact.hpp) to the
// simulated hardware (plant/runtime/simulated_hardware.hpp). On a compiled loop, an effect set
// that ComposedEffectSets lists is composed at compile time: each effect the artefact carries
// picks its type, each one it leaves out picks NoEffect. Every other set, and every set on the
// general path, runs in one composition whose slots are chosen at start-up (EffectChoice): the
// build instantiates what runs fast, not every combination (2 floors x 3 actuators x 2 x 2
// sensors x 2 transports). NW disturbances, NC actuators, NS sensors: compiled counts, or
// Eigen::Dynamic for the general path, where the artefact's channel map sizes everything.
//
// The floor's own position and velocity: a gravity-preloaded plant has them as states (the
// dynamics depend on where the floor is). They start where the floor generator's floor is
// (FloorGenerator::motion), so that the plant integrates the same stationary floor the generator
// draws; started at rest they would carry the floor's initial velocity as a constant offset and
// the floor would drift away at it (millimetres in seconds, which the soft force-feedback loop
// turns into kilonewtons). A white floor acceleration has no stationary displacement: a plant
// with floor states refuses it.
#include <string>
#include <utility>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "online/sim/loop_start.hpp"
#include "plant/runtime/compiled_loops.hpp"
#include "plant/runtime/effect_choice.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "plant/runtime/effects/sensor_chain.hpp"
#include "plant/runtime/effects/white_floor.hpp"
#include "plant/runtime/simulated_hardware.hpp"

namespace flexloop::sim {

namespace fx = plant::runtime::effects;
using artefact::has_effects;
using plant::runtime::NoEffect;

using artefact::kFloorFilterOrder;

template <int N>
fx::SensorParameters<N> sensor_parameters(const artefact::SensorEffect& e, Eigen::Index n = N) {
  fx::SensorParameters<N> p(n);
  p.gain_error.setConstant(e.gain_error);
  p.noise_rms.setConstant(e.noise_rms);
  p.adc_bits = e.adc_bits;
  p.adc_range.setConstant(e.adc_range);
  p.delay_samples = e.delay_samples;
  p.seed = e.seed;
  return p;
}

/// The plant with its floor states (labels "pos:<c>", "vel:<c>" for a disturbance "acc:<c>",
/// among the artefact's plant states) set to the floor's start; the plant as it is when it has
/// none. @throws flexloop::InputError for floor states with a white floor or a method other than
/// zoh.
template <class Plant, class Floor>
Plant plant_at_floor_start(Plant plant, const Floor& floor, const artefact::LoopArtefact& a) {
  const auto floor_states = artefact::floor_states(a);
  const bool any = !floor_states.empty();
  if (!any) return plant;
  // The floor's entries of the physical state; a modal plant takes T^-1 x (its floor blocks keep
  // the floor's states, the structure's coordinates are relative to them).
  const auto at_floor = [&](auto x) {
    if constexpr (requires { floor.motion(); })
      for (const auto& f : floor_states) x(f.state) = floor.motion()(f.motion_row, f.channel);
    return x;
  };
  if (any && !requires { floor.motion(); })
    throw common::InputError(
        a.source,
        "[floor]: this plant has the floor's position as a state (gravity preload), "
        "and a white floor acceleration has no stationary position (it would drift "
        "as a random walk); use a VC spectrum");
  // Only the zero-order hold keeps the continuous state as the discrete one; Tustin, FOH and
  // backward Euler use shifted or scaled coordinates (plant/lti/discretise.hpp).
  if (any && a.method != artefact::DiscretisationMethod::kZeroOrderHold)
    throw common::InputError(
        a.source,
        "[discretisation]: this plant has the floor's position and velocity as "
        "states (gravity preload), which start where the floor is; that needs "
        "method = \"zoh\" (the other methods' states are other coordinates)");
  if constexpr (requires(const Plant p) { p.physical_state(); })
    plant.set_state(
        plant_coordinates<Plant>(a, at_floor(Eigen::VectorXd::Zero(a.plant.A.rows()).eval())));
  else
    plant.set_state(at_floor(plant.state()));
  return plant;
}

/// What a loop's simulated hardware is made of: the floor's kind and the effects present.
enum class ActuatorKind { kNone, kPiezo, kLaggedPiezo };
struct EffectSet {
  bool vc_floor = false;  ///< a VC curve's shaping filter; false: white
  ActuatorKind actuator = ActuatorKind::kNone;
  bool force_sensor = false, accelerometer = false, transport_delay = false;
  friend bool operator==(const EffectSet&, const EffectSet&) = default;
};

inline EffectSet effect_set(const artefact::LoopArtefact& a) {
  const auto& e = a.effects;
  return {.vc_floor = a.floor.spectrum != artefact::FloorSpectrum::kWhite,
          .actuator = !e.actuator.present    ? ActuatorKind::kNone
                      : e.actuator.lag_s > 0 ? ActuatorKind::kLaggedPiezo
                                             : ActuatorKind::kPiezo,
          .force_sensor = e.force_sensor.present,
          .accelerometer = e.accelerometer.present,
          .transport_delay = e.transport_delay_samples > 0};
}

/// One effect set with a composition of its own on the compiled loops.
template <bool VcFloor, ActuatorKind Actuator, bool ForceSensor, bool Accelerometer,
          bool TransportDelay>
struct ComposedEffects {
  static constexpr EffectSet kSet{.vc_floor = VcFloor,
                                  .actuator = Actuator,
                                  .force_sensor = ForceSensor,
                                  .accelerometer = Accelerometer,
                                  .transport_delay = TransportDelay};
};

/// The effect sets that the compiled loops (plant/runtime/compiled_loops.hpp) run in a
/// composition of their own, every absent effect NoEffect: not stored, not stepped, not tested
/// for. Every other set, on any loop, runs in the composition chosen at start-up
/// (with_chosen_hardware), one instantiation for all of them. Each entry costs one instantiation
/// of every loop body per compiled loop: list the sets whose speed is measured and promised.
using ComposedEffectSets = plant::runtime::TypeList<
    ComposedEffects<true, ActuatorKind::kPiezo, true, true, false>,  // metrology_frame.toml
    ComposedEffects<true, ActuatorKind::kLaggedPiezo, true, true,
                    true>,                                              // _all_effects
    ComposedEffects<false, ActuatorKind::kNone, false, false, false>>;  // _bare

/// The artefact's floor: a VC curve's shaping filter (VcFloor), or white.
template <int NW, bool VcFloor>
auto make_floor(const artefact::LoopArtefact& a) {
  const Eigen::Index nw = a.disturbances();
  if constexpr (VcFloor) {
    const auto& filter = a.floor_filter;
    auto floor = fx::FloorGenerator<double, NW, kFloorFilterOrder>::from_parameters(
        filter.A, filter.B, filter.C, filter.D, a.floor.seed, fx::FloorStart::kStationary, nw);
    floor.set_motion_outputs(filter.motion);
    return floor;
  } else {
    return fx::WhiteFloor<double, NW>::from_parameters(a.floor.rms_mps2, a.floor.seed, nw);
  }
}

/// The floor filters' states at the start of a run (order x channels; empty for a white floor):
/// what the floor generator of any run of `a` draws, for a process without a floor of its own.
inline Eigen::MatrixXd floor_start_states(const artefact::LoopArtefact& a) {
  if (a.floor.spectrum == artefact::FloorSpectrum::kWhite) return {};
  return make_floor<Eigen::Dynamic, true>(a).state().template cast<double>();
}

/// The artefact's floor alone (white or a VC curve): f(floor).
template <int NW, class F>
decltype(auto) with_floor(const artefact::LoopArtefact& a, F&& f) {
  if (a.floor.spectrum == artefact::FloorSpectrum::kWhite) return f(make_floor<NW, false>(a));
  return f(make_floor<NW, true>(a));
}

/// The artefact's actuator as the given kind (NoEffect for kNone).
template <int NC, ActuatorKind Kind>
auto make_actuator(const artefact::LoopArtefact& a) {
  if constexpr (Kind == ActuatorKind::kNone) {
    return NoEffect{};
  } else {
    const auto& e = a.effects.actuator;
    fx::PiezoActuatorParameters<NC> p(a.actuators());
    p.gain.setConstant(e.gain);
    p.force_min.setConstant(-e.force_limit_n);
    p.force_max.setConstant(e.force_limit_n);
    constexpr bool kLagged = Kind == ActuatorKind::kLaggedPiezo;
    if constexpr (kLagged) p.lag_time_constant.setConstant(e.lag_s);
    return fx::PiezoActuator<double, NC, kLagged>::from_parameters(p, a.dt());
  }
}

/// A sensor chain of n channels (NoEffect unless Present).
template <int N, bool Present>
auto make_sensor_chain(const artefact::SensorEffect& e, Eigen::Index n) {
  if constexpr (Present)
    return fx::SensorChain<double, N>::from_parameters(sensor_parameters<N>(e, n));
  else
    return NoEffect{};
}

/// The transport delay of the artefact (NoEffect unless Present).
template <int NS, int NZ, bool Present>
auto make_transport_delay(const artefact::LoopArtefact& a) {
  if constexpr (Present)
    return fx::TransportDelay<double, NS, NZ>::from_parameters(a.effects.transport_delay_samples,
                                                               a.sensors(), a.performance());
  else
    return NoEffect{};
}

/// The hardware of these effects around the plant, started where the floor is.
template <int NW, int NC, int NS, class Plant, class Floor, class Actuator, class Sensor,
          class Performance, class Transport>
auto compose_hardware(const artefact::LoopArtefact& a, const Plant& plant, Floor floor,
                      Actuator actuator, Sensor sensor, Performance performance,
                      Transport transport) {
  Plant started = plant_at_floor_start(plant, floor, a);
  return plant::runtime::SimulatedHardware<Plant, NW, NC, Floor, Actuator, Sensor, Performance,
                                           Transport, NS>(
      std::move(started), std::move(floor), std::move(actuator), std::move(sensor),
      std::move(performance), std::move(transport), a.sensors());
}

/// f(hardware): the plant with the artefact's floor and every effect it carries, each slot's
/// effect chosen at start-up (plant/runtime/effect_choice.hpp): two instantiations (white or VC
/// floor) serve every effect set. An absent transport delay is a delay of 0 samples, which passes
/// the reading through.
template <int NW, int NC, int NS = NC, class Plant, class F>
decltype(auto) with_chosen_hardware(const artefact::LoopArtefact& a, const Plant& plant, F&& f) {
  constexpr int NY = Plant::Output::RowsAtCompileTime;
  constexpr int NZ = NY == Eigen::Dynamic || NS == Eigen::Dynamic ? Eigen::Dynamic : NY - NS;
  using plant::runtime::EffectChoice;
  using Actuator =
      EffectChoice<numeric::ChannelsOf<double, NC>, fx::PiezoActuator<double, NC, false>,
                   fx::PiezoActuator<double, NC, true>>;
  using Sensor = EffectChoice<numeric::ChannelsOf<double, NS>, fx::SensorChain<double, NS>>;
  using Performance = EffectChoice<numeric::ChannelsOf<double, NZ>, fx::SensorChain<double, NZ>>;
  const EffectSet set = effect_set(a);
  const auto& e = a.effects;
  Actuator actuator;
  if (set.actuator == ActuatorKind::kPiezo)
    actuator = Actuator(make_actuator<NC, ActuatorKind::kPiezo>(a));
  else if (set.actuator == ActuatorKind::kLaggedPiezo)
    actuator = Actuator(make_actuator<NC, ActuatorKind::kLaggedPiezo>(a));
  const Sensor sensor = set.force_sensor
                            ? Sensor(make_sensor_chain<NS, true>(e.force_sensor, a.sensors()))
                            : Sensor();
  const Performance performance =
      set.accelerometer ? Performance(make_sensor_chain<NZ, true>(e.accelerometer, a.performance()))
                        : Performance();
  return with_floor<NW>(a, [&](auto floor) -> decltype(auto) {
    return f(compose_hardware<NW, NC, NS>(a, plant, std::move(floor), actuator, sensor, performance,
                                          make_transport_delay<NS, NZ, true>(a)));
  });
}

/// f(hardware): the plant with the artefact's floor and every effect it carries. On a compiled
/// loop whose effect set ComposedEffectSets lists, the hardware is composed at compile time for
/// that set; otherwise its slots are chosen at start-up (with_chosen_hardware).
template <int NW, int NC, int NS = NC, class Plant, class F>
decltype(auto) with_hardware(const artefact::LoopArtefact& a, const Plant& plant, F&& f) {
  constexpr bool kCompiled = NW != Eigen::Dynamic && NC != Eigen::Dynamic && NS != Eigen::Dynamic;
  if constexpr (!kCompiled) {
    return with_chosen_hardware<NW, NC, NS>(a, plant, f);
  } else {
    constexpr int NZ = Plant::Output::RowsAtCompileTime - NS;
    const EffectSet set = effect_set(a);
    return plant::runtime::first_match(
        ComposedEffectSets{}, [&set](auto listed) { return decltype(listed)::kSet == set; },
        [&](auto listed) -> decltype(auto) {
          constexpr EffectSet s = decltype(listed)::kSet;
          const auto& e = a.effects;
          return f(compose_hardware<NW, NC, NS>(
              a, plant, make_floor<NW, s.vc_floor>(a), make_actuator<NC, s.actuator>(a),
              make_sensor_chain<NS, s.force_sensor>(e.force_sensor, a.sensors()),
              make_sensor_chain<NZ, s.accelerometer>(e.accelerometer, a.performance()),
              make_transport_delay<NS, NZ, s.transport_delay>(a)));
        },
        [&]() -> decltype(auto) { return with_chosen_hardware<NW, NC, NS>(a, plant, f); });
  }
}

/// The plant with the artefact's floor and no other effect (a bare loop: one composition per
/// floor). @throws flexloop::InputError naming the artefact when it carries
/// effects.
template <int NW, int NC, int NS = NC, class Plant, class F>
decltype(auto) with_bare_hardware(const artefact::LoopArtefact& a, const Plant& plant, F&& f) {
  if (has_effects(a.effects))
    throw common::InputError(a.source,
                             "[effects]: a bare loop runs without hardware effects; compose them "
                             "with with_hardware");
  return with_floor<NW>(a, [&](auto floor) -> decltype(auto) {
    return f(compose_hardware<NW, NC, NS>(a, plant, std::move(floor), NoEffect{}, NoEffect{},
                                          NoEffect{}, NoEffect{}));
  });
}

}  // namespace flexloop::sim
