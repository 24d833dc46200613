#pragma once
// Start-up: from a loop artefact's floor and effects (artefact/loop_artefact.hpp) to the
// compile-time composition of the simulated hardware (plant/runtime/simulated_hardware.hpp).
// Each effect the artefact carries picks its type; each one it leaves out picks NoEffect. `f` is
// called with the composed hardware (one instantiation per combination: 2 floors x 3 actuators x
// 2 x 2 sensors x 2 transports). NW disturbances, NC actuators, NS sensors: compiled counts, or
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
#include "online/numeric/compiled_loops.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "plant/runtime/effects/sensor_chain.hpp"
#include "plant/runtime/effects/white_floor.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "plant/runtime/simulated_hardware.hpp"

namespace flexloop::sim {

namespace fx = plant::runtime::effects;
using artefact::has_effects;
using plant::runtime::NoEffect;

using artefact::kFloorFilterOrder;

/// The artefact's counts and plant form, as the dispatch to a compiled loop compares them.
inline plant::runtime::LoopCounts loop_counts(const artefact::LoopArtefact& a) {
  return {.states = a.plant.A.rows(),
          .disturbances = a.disturbances(),
          .actuators = a.actuators(),
          .performance = a.performance(),
          .sensors = a.sensors(),
          .form = a.plant.form == "modal" ? plant::runtime::PlantForm::kModal
                                          : plant::runtime::PlantForm::kDense};
}

/// The artefact's plant on the fixed-size kernels of a compiled loop (its counts match Loop).
template <class Loop>
auto make_compiled_plant(const artefact::LoopArtefact& a) {
  const auto& d = a.plant;
  if constexpr (Loop::kForm == plant::runtime::PlantForm::kModal)
    return plant::runtime::ModalPlant<double, Loop::NX, Loop::NU, Loop::NY,
                                      Loop::NH>::from_modal_form(d.modal);
  else
    return plant::runtime::DensePlant<double, Loop::NX, Loop::NU, Loop::NY,
                                      Loop::NH>::from_matrices(d.A, d.B, d.C, d.D);
}

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
  typename Plant::State x = plant.state();
  const auto& states = a.plant.states;
  bool any = false;
  for (std::size_t c = 0; c < a.channels.disturbances.size(); ++c) {
    const std::string& name = a.channels.disturbances[c].name;
    if (name.rfind("acc:", 0) != 0) continue;
    const std::string coordinate = name.substr(4);
    for (std::size_t i = 0; i < states.size(); ++i) {
      const bool vel = states[i] == "vel:" + coordinate, pos = states[i] == "pos:" + coordinate;
      if (!vel && !pos) continue;
      any = true;
      if constexpr (requires { floor.motion(); })
        x(static_cast<Eigen::Index>(i)) = floor.motion()(pos ? 1 : 0, static_cast<Eigen::Index>(c));
    }
  }
  if (any && !requires { floor.motion(); })
    throw InputError(a.source,
                     "[floor]: this plant has the floor's position as a state (gravity preload), "
                     "and a white floor acceleration has no stationary position (it would drift "
                     "as a random walk); use a VC spectrum");
  // Only the zero-order hold keeps the continuous state as the discrete one; Tustin, FOH and
  // backward Euler use shifted or scaled coordinates (plant/lti/discretise.hpp).
  if (any && a.method != "zoh")
    throw InputError(a.source,
                     "[discretisation]: this plant has the floor's position and velocity as "
                     "states (gravity preload), which start where the floor is; that needs "
                     "method = \"zoh\" (the other methods' states are other coordinates)");
  plant.set_state(x);
  return plant;
}

/// The artefact's floor alone (white or a VC curve): f(floor).
template <int NW, class F>
decltype(auto) with_floor(const artefact::LoopArtefact& a, F&& f) {
  const Eigen::Index nw = a.disturbances();
  if (a.floor.spectrum == "white")
    return f(fx::WhiteFloor<double, NW>::from_parameters(a.floor.rms_mps2, a.floor.seed, nw));
  const auto& filter = a.floor_filter;
  auto floor = fx::FloorGenerator<double, NW, kFloorFilterOrder>::from_parameters(
      filter.A, filter.B, filter.C, filter.D, a.floor.seed, fx::FloorStart::kStationary, nw);
  floor.set_motion_outputs(filter.motion);
  return f(std::move(floor));
}

/// f(hardware): the plant with the artefact's floor and every effect it carries.
template <int NW, int NC, int NS = NC, class Plant, class F>
decltype(auto) with_hardware(const artefact::LoopArtefact& a, const Plant& plant, F&& f) {
  constexpr int NY = Plant::Output::RowsAtCompileTime;
  constexpr int NZ = NY == Eigen::Dynamic || NS == Eigen::Dynamic ? Eigen::Dynamic : NY - NS;
  const Eigen::Index ns = a.sensors(), nz = a.performance();
  const auto& e = a.effects;
  auto with_transport = [&](auto floor, auto actuator, auto sensor,
                            auto performance) -> decltype(auto) {
    auto make = [&](auto transport) -> decltype(auto) {
      return f(plant::runtime::SimulatedHardware<Plant, NW, NC, decltype(floor), decltype(actuator),
                                                 decltype(sensor), decltype(performance),
                                                 decltype(transport), NS>(
          plant_at_floor_start(plant, floor, a), floor, actuator, sensor, performance, transport,
          ns));
    };
    if (e.transport_delay_samples > 0)
      return make(
          fx::TransportDelay<double, NS, NZ>::from_parameters(e.transport_delay_samples, ns, nz));
    return make(NoEffect{});
  };
  auto with_performance = [&](auto floor, auto actuator, auto sensor) -> decltype(auto) {
    if (e.accelerometer.present)
      return with_transport(
          floor, actuator, sensor,
          fx::SensorChain<double, NZ>::from_parameters(sensor_parameters<NZ>(e.accelerometer, nz)));
    return with_transport(floor, actuator, sensor, NoEffect{});
  };
  auto with_sensor = [&](auto floor, auto actuator) -> decltype(auto) {
    if (e.force_sensor.present)
      return with_performance(
          floor, actuator,
          fx::SensorChain<double, NS>::from_parameters(sensor_parameters<NS>(e.force_sensor, ns)));
    return with_performance(floor, actuator, NoEffect{});
  };
  auto with_actuator = [&](auto floor) -> decltype(auto) {
    if (!e.actuator.present) return with_sensor(floor, NoEffect{});
    fx::PiezoActuatorParameters<NC> p(a.actuators());
    p.gain.setConstant(e.actuator.gain);
    p.force_min.setConstant(-e.actuator.force_limit_n);
    p.force_max.setConstant(e.actuator.force_limit_n);
    if (e.actuator.lag_s > 0) {
      p.lag_time_constant.setConstant(e.actuator.lag_s);
      return with_sensor(floor, fx::PiezoActuator<double, NC, true>::from_parameters(p, a.dt()));
    }
    return with_sensor(floor, fx::PiezoActuator<double, NC, false>::from_parameters(p, a.dt()));
  };
  return with_floor<NW>(a, with_actuator);
}

/// The plant with the artefact's floor and no other effect (a bare loop: one composition instead
/// of every effect combination). @throws flexloop::InputError naming the artefact when it carries
/// effects.
template <int NW, int NC, int NS = NC, class Plant, class F>
decltype(auto) with_bare_hardware(const artefact::LoopArtefact& a, const Plant& plant, F&& f) {
  if (has_effects(a.effects))
    throw InputError(a.source,
                     "[effects]: a bare loop runs without hardware effects; compose them "
                     "with with_hardware");
  return with_floor<NW>(a, [&](auto floor) -> decltype(auto) {
    return f(plant::runtime::SimulatedHardware<Plant, NW, NC, decltype(floor), NoEffect, NoEffect,
                                               NoEffect, NoEffect, NS>(
        plant_at_floor_start(plant, floor, a), floor, {}, {}, {}, {}, a.sensors()));
  });
}

}  // namespace flexloop::sim
