// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A run's start (doc/design.md §5a, artefact/loop_start.hpp): the loop's states drawn from its
// stationary distribution given the floor filters' states, which the floor generator has drawn
// with its own seed; or at rest. Start-up only (allocates).
//
// What is set: the plant's state (the floor's own position and velocity at the floor's motion),
// the actuator force held since the last sample, the actuator lag's force, the delay lines of
// the sensors and of the transport (d samples; the ADC's rounding left out), the controller's
// state and the commands it remembers. The performance channels' transport line, which feeds
// nothing back, starts empty.
#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <type_traits>

#include "artefact/loop_artefact.hpp"
#include "numeric/stationary_covariance.hpp"
#include "plant/runtime/effects/gaussian_noise.hpp"
#include "plant/runtime/simulated_hardware.hpp"

namespace flexloop::sim {

enum class StartKind { kStationary, kRest };

/// The rows of a start (artefact/loop_start.hpp) split where they live.
struct DrawnStart {
  Eigen::VectorXd plant_state;      ///< x, the artefact's dense coordinates
  Eigen::VectorXd held_force;       ///< h
  Eigen::VectorXd sensor_history;   ///< s_{k-1} .. s_{k-d}, before the sensors' gain error
  Eigen::VectorXd command_history;  ///< u_{k-1} .. u_{k-1-d}
  Eigen::VectorXd last_command;     ///< u_{k-1}
  Eigen::VectorXd controller;       ///< xc
  Eigen::VectorXd lag;              ///< l (zero without a lag)
};

/// The seed of a start's own draws: the floor's seed, marked ("start" in ASCII), so that the
/// floor draws what it draws from rest and the same seeds give the same start.
inline std::uint64_t start_seed(const artefact::LoopArtefact& a) {
  return a.floor.seed ^ 0x7374617274ull;
}

/// rows = floor_gain * floor + root(covariance) * z, z standard normal from start_seed(a).
/// floor: the floor filters' states, order x channels (a white floor: empty).
inline DrawnStart draw_start(const artefact::LoopArtefact& a, const artefact::StationaryStart& s,
                             const Eigen::MatrixXd& floor) {
  const Eigen::Index n = s.covariance.rows(), nx = a.plant.A.rows(), nc = a.actuators(),
                     ns = a.sensors();
  auto noise =
      plant::runtime::effects::GaussianNoise<double, Eigen::Dynamic>::from_seed(start_seed(a), 1);
  Eigen::VectorXd z(n);
  for (Eigen::Index i = 0; i < n; ++i) z(i) = noise.sample(0);
  Eigen::VectorXd rows = numeric::covariance_root(s.covariance) * z;
  if (s.floor_gain.cols() > 0)
    rows += s.floor_gain * Eigen::Map<const Eigen::VectorXd>(floor.data(), floor.size());
  DrawnStart d;
  Eigen::Index at = 0;
  const auto take = [&](Eigen::Index count) {
    Eigen::VectorXd v = rows.segment(at, count);
    at += count;
    return v;
  };
  d.plant_state = take(nx);
  d.held_force = take(nc);
  d.sensor_history = take(s.delay * ns);
  d.command_history = take((s.delay + 1) * nc);
  d.last_command = d.command_history.head(nc);
  d.controller = take(s.controller_states);
  d.lag = s.actuator_lag ? take(nc) : Eigen::VectorXd::Zero(nc);
  return d;
}

/// The floor filters' states of the hardware's floor, order x channels (empty for a white floor).
template <class Hardware>
Eigen::MatrixXd floor_filter_states(const Hardware& hw) {
  if constexpr (requires { hw.floor().state(); })
    return hw.floor().state().template cast<double>();
  else
    return Eigen::MatrixXd();
}

/// The plant state in the runtime plant's own coordinates: the modal state T⁻¹ x for a modal
/// plant, x itself for a dense one.
template <class Plant>
typename Plant::State plant_coordinates(const artefact::LoopArtefact& a, const Eigen::VectorXd& x) {
  if constexpr (requires(const Plant p) { p.physical_state(); })
    return a.plant.modal.T.partialPivLu().solve(x).template cast<typename Plant::State::Scalar>();
  else
    return x.cast<typename Plant::State::Scalar>();
}

/// What a run says about its start, e.g. "start: stationary (closed loop)" or "start: at rest
/// (the loop has no stationary state: ...)".
inline std::string describe_start(StartKind kind, const artefact::StationaryStart& s,
                                  const char* loop) {
  if (kind == StartKind::kRest) return "at rest (--start rest)";
  if (!s.exists())
    return "at rest: the " + std::string(loop) + " has no stationary start (" + s.unavailable + ")";
  return "stationary (" + std::string(loop) + (s.note.empty() ? "" : "; " + s.note) + ")";
}

/// The start of a real-time run (flexloop plant, controller, hil): the closed loop's when the
/// artefact has a controller (its process closes the loop), the plant's alone otherwise. The
/// plant and the controller process draw it alike (same artefact, same seeds).
inline const artefact::StationaryStart& run_start(const artefact::LoopArtefact& a) {
  return a.controller == artefact::ControllerKind::kNone ? a.start.open_loop : a.start.closed_loop;
}
inline const char* run_loop_name(const artefact::LoopArtefact& a) {
  return a.controller == artefact::ControllerKind::kNone ? "open loop" : "closed loop";
}

/// Sets the hardware to a drawn start: plant state, held force, actuator lag.
template <class Hardware>
void start_hardware_at(const artefact::LoopArtefact& a, const DrawnStart& d, Hardware& hw) {
  using Plant = std::decay_t<decltype(hw.plant())>;
  using Command = typename Hardware::Command;
  using Scalar = typename Hardware::Scalar;
  hw.start_at(plant_coordinates<Plant>(a, d.plant_state), Command(d.held_force.cast<Scalar>()),
              Command(d.lag.cast<Scalar>()));
  const Eigen::Index ns = a.sensors();
  if (d.sensor_history.size() == 0) return;
  const double gain = a.effects.force_sensor.present ? 1 + a.effects.force_sensor.gain_error : 1;
  using Sensors = typename Hardware::Sensors;
  hw.start_sensor_lines([&](int j) {
    return Sensors((gain * d.sensor_history.segment((j - 1) * ns, ns)).template cast<Scalar>());
  });
}

/// Sets the controller to a drawn start: its state and the commands it remembers.
template <class Controller>
void start_controller_at(const DrawnStart& d, Controller& controller) {
  using Vector = typename Controller::Vector;
  using Scalar = typename Vector::Scalar;
  controller.set_state(d.controller);  // a state-space controller's may exceed a Vector
  const Eigen::Index nc = d.last_command.size();
  for (Eigen::Index j = d.command_history.size() / nc - 1; j >= 0; --j)
    controller.set_earlier_command(
        static_cast<int>(j), Vector(d.command_history.segment(j * nc, nc).template cast<Scalar>()));
}

/// Sets the hardware and the controller to the start. Returns false when the loop starts at rest
/// (kind kRest, or no stationary start).
template <class Hardware, class Controller>
bool start_loop(const artefact::LoopArtefact& a, const artefact::StationaryStart& s, StartKind kind,
                Hardware& hw, Controller& controller) {
  if (kind == StartKind::kRest || !s.exists()) return false;
  const DrawnStart d = draw_start(a, s, floor_filter_states(hw));
  start_hardware_at(a, d, hw);
  if constexpr (plant::runtime::kPresent<Controller>) start_controller_at(d, controller);
  return true;
}

}  // namespace flexloop::sim
