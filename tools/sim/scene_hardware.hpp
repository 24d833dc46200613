#pragma once
// Start-up: from a scene's [floor] and [effects] tables to the compile-time composition of the
// simulated hardware (plant/runtime/simulated_hardware.hpp). Each effect the scene asks for picks
// its type; each one it leaves out picks NoEffect. `f` is called with the composed hardware
// (one instantiation per combination: 2 floors x 3 actuators x 2 x 2 sensors x 2 transports).
//
// The floor's own position and velocity: a gravity-preloaded plant has them as states (the
// dynamics depend on where the floor is). They start where the floor generator's floor is
// (FloorGenerator::motion), so that the plant integrates the same stationary floor the generator
// draws; started at rest they would carry the floor's initial velocity as a constant offset and
// the floor would drift away at it (millimetres in seconds, which the soft force-feedback loop
// turns into kilonewtons). A white floor acceleration has no stationary displacement: a plant
// with floor states refuses it.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/vibration_criterion.hpp"
#include "plant/model/input_error.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "plant/runtime/effects/sensor_chain.hpp"
#include "plant/runtime/effects/white_floor.hpp"
#include "plant/runtime/simulated_hardware.hpp"
#include "tools/scene/pi_parameters.hpp"
#include "tools/scene/scene_plant.hpp"

namespace flexloop::sim {

namespace fx = plant::runtime::effects;
using plant::runtime::NoEffect;

template <int N>
fx::SensorParameters<N> sensor_parameters(const scene::SensorEffect& e) {
  fx::SensorParameters<N> p;
  p.gain_error.setConstant(e.gain_error);
  p.noise_rms.setConstant(e.noise_rms);
  p.adc_bits = e.adc_bits;
  p.adc_range.setConstant(e.adc_range);
  p.delay_samples = e.delay_samples;
  p.seed = e.seed;
  return p;
}

template <int NW, class F>
decltype(auto) with_scene_floor(const scene::Scene& sc, double dt, F&& f);

/// The plant with its floor states (labels "pos:<c>", "vel:<c>" for a disturbance "acc:<c>",
/// among `states`, the sampled plant's state labels) set to the floor's start; the plant as it
/// is when it has none. @throws flexloop::InputError for floor states with a white floor.
template <class Plant, class Floor>
Plant plant_at_floor_start(Plant plant, const Floor& floor, const scene::Scene& sc,
                           const std::vector<std::string>& states) {
  typename Plant::State x = plant.state();
  bool any = false;
  for (std::size_t c = 0; c < sc.disturbances.size(); ++c) {
    const std::string& name = sc.disturbances[c];
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
    throw InputError(sc.file,
                     "[floor]: this plant has the floor's position as a state (gravity preload), "
                     "and a white floor acceleration has no stationary position (it would drift "
                     "as a random walk); use a VC spectrum");
  // Only the zero-order hold keeps the continuous state as the discrete one; Tustin, FOH and
  // backward Euler use shifted or scaled coordinates (plant/lti/discretise.hpp).
  if (any && sc.discretisation.method != plant::lti::DiscretisationMethod::kZeroOrderHold)
    throw InputError(sc.file,
                     "[discretisation]: this plant has the floor's position and velocity as "
                     "states (gravity preload), which start where the floor is; that needs "
                     "method = \"zoh\" (the other methods' states are other coordinates)");
  plant.set_state(x);
  return plant;
}

template <int NW, int NC, class Plant, class F>
decltype(auto) with_scene_hardware(const scene::Scene& sc, const Plant& plant,
                                   const std::vector<std::string>& plant_states, double dt, F&& f) {
  constexpr int NZ = Plant::Output::RowsAtCompileTime - NC;
  const auto& e = sc.effects;
  auto with_transport = [&](auto floor, auto actuator, auto force, auto accel) -> decltype(auto) {
    auto make = [&](auto transport) -> decltype(auto) {
      return f(
          plant::runtime::SimulatedHardware<Plant, NW, NC, decltype(floor), decltype(actuator),
                                            decltype(force), decltype(accel), decltype(transport)>(
              plant_at_floor_start(plant, floor, sc, plant_states), floor, actuator, force, accel,
              transport));
    };
    if (e.transport_delay_samples > 0)
      return make(fx::SampleDelay<double, NC + NZ>::from_parameters(e.transport_delay_samples));
    return make(NoEffect{});
  };
  auto with_accel = [&](auto floor, auto actuator, auto force) -> decltype(auto) {
    if (e.accelerometer.present)
      return with_transport(
          floor, actuator, force,
          fx::SensorChain<double, NZ>::from_parameters(sensor_parameters<NZ>(e.accelerometer)));
    return with_transport(floor, actuator, force, NoEffect{});
  };
  auto with_force = [&](auto floor, auto actuator) -> decltype(auto) {
    if (e.force_sensor.present)
      return with_accel(
          floor, actuator,
          fx::SensorChain<double, NC>::from_parameters(sensor_parameters<NC>(e.force_sensor)));
    return with_accel(floor, actuator, NoEffect{});
  };
  auto with_actuator = [&](auto floor) -> decltype(auto) {
    if (!e.actuator.present) return with_force(floor, NoEffect{});
    fx::PiezoActuatorParameters<NC> p;
    p.gain.setConstant(e.actuator.gain);
    p.force_min.setConstant(-e.actuator.force_limit_n);
    p.force_max.setConstant(e.actuator.force_limit_n);
    if (e.actuator.lag_s > 0) {
      p.lag_time_constant.setConstant(e.actuator.lag_s);
      return with_force(floor, fx::PiezoActuator<double, NC, true>::from_parameters(p, dt));
    }
    return with_force(floor, fx::PiezoActuator<double, NC, false>::from_parameters(p, dt));
  };
  return with_scene_floor<NW>(sc, dt, with_actuator);
}

/// The scene's floor alone (white or a VC curve): f(floor).
template <int NW, class F>
decltype(auto) with_scene_floor(const scene::Scene& sc, double dt, F&& f) {
  if (sc.floor.spectrum == "white")
    return f(fx::WhiteFloor<double, NW>::from_parameters(sc.floor.rms_mps2, sc.floor.seed));
  const auto continuous = plant::lti::design_floor_filter(plant::lti::criterion_band_velocity_rms(
      plant::lti::parse_vibration_criterion(sc.floor.spectrum)));
  const auto filter = plant::lti::discretise_floor_filter(continuous, dt);
  auto floor = fx::FloorGenerator<double, NW, plant::lti::kFloorFilterOrder>::from_parameters(
      filter.sys.A, filter.sys.B, filter.sys.C, filter.sys.D, sc.floor.seed);
  floor.set_motion_outputs(plant::lti::floor_motion_outputs(continuous));
  return f(std::move(floor));
}

inline bool has_effects(const scene::EffectsSettings& e) {
  return e.actuator.present || e.force_sensor.present || e.accelerometer.present ||
         e.transport_delay_samples > 0;
}

/// The plant with the scene's floor and no other effect (other plant sizes and forms are
/// compiled without the effect combinations, to keep the build short).
/// @throws flexloop::InputError naming the scene when it asks for effects.
template <int NW, int NC, class Plant, class F>
decltype(auto) with_bare_hardware(const scene::Scene& sc, const Plant& plant,
                                  const std::vector<std::string>& plant_states, double dt, F&& f) {
  if (has_effects(sc.effects))
    throw InputError(sc.file,
                     "[effects]: hardware effects are compiled for the dense 12-state "
                     "metrology plant only; remove [effects] or use --form dense");
  return with_scene_floor<NW>(sc, dt, [&](auto floor) -> decltype(auto) {
    return f(plant::runtime::SimulatedHardware<Plant, NW, NC, decltype(floor)>(
        plant_at_floor_start(plant, floor, sc, plant_states), floor));
  });
}

/// The PI parameters of a scene with its hardware effects: the controller knows how late its
/// own force reaches it (sensor delay + transport delay) and limits its commands to what the
/// actuator can give (anti-windup).
inline controller::runtime::PiParameters pi_parameters_with_hardware(const scene::ScenePlant& p,
                                                                     double dt) {
  controller::runtime::PiParameters pi = scene::pi_parameters(p, dt);
  const auto& e = p.scene.effects;
  pi.feedthrough_delay =
      (e.force_sensor.present ? e.force_sensor.delay_samples : 0) + e.transport_delay_samples;
  if (e.actuator.present) {
    const double limit = std::min(p.scene.controller.force_limit_n,
                                  e.actuator.force_limit_n / std::abs(e.actuator.gain));
    pi.u_min = Eigen::VectorXd::Constant(1, -limit);
    pi.u_max = Eigen::VectorXd::Constant(1, limit);
  }
  return pi;
}

}  // namespace flexloop::sim
