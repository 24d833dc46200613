#pragma once
// A run's start (doc/design.md §5a, artefact/loop_start.hpp): the loop's states drawn from its
// stationary distribution given the floor filters' states, which the floor generator has drawn
// with its own seed; or at rest. Start-up only (allocates).
//
// What is set: the plant's state (the floor's own position and velocity at the floor's motion),
// the actuator force held since the last sample, the actuator lag's force, the controller's state
// and its last command. The delay lines of the sensors and of the transport (d > 0 samples) start
// empty, as from rest: the controller sees zeros for d samples.
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
  Eigen::VectorXd plant_state;   ///< x, the artefact's dense coordinates
  Eigen::VectorXd held_force;    ///< h
  Eigen::VectorXd last_command;  ///< u_{k-1}
  Eigen::VectorXd controller;    ///< xc
  Eigen::VectorXd lag;           ///< l (zero without a lag)
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
  take(s.delay * ns);  // the sensor history: the delay lines start empty
  d.last_command = take(nc);
  take(s.delay * nc);
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

/// Sets the hardware (and the controller, when there is one) to the start. Returns false when
/// the loop starts at rest (kind kRest, or no stationary start).
template <class Hardware, class Controller>
bool start_loop(const artefact::LoopArtefact& a, const artefact::StationaryStart& s, StartKind kind,
                Hardware& hw, Controller* controller) {
  if (kind == StartKind::kRest || !s.exists()) return false;
  const DrawnStart d = draw_start(a, s, floor_filter_states(hw));
  using Plant = std::decay_t<decltype(hw.plant())>;
  using Command = typename Hardware::Command;
  using Scalar = typename Hardware::Scalar;
  hw.start_at(plant_coordinates<Plant>(a, d.plant_state), Command(d.held_force.cast<Scalar>()),
              Command(d.lag.cast<Scalar>()));
  if constexpr (plant::runtime::kPresent<Controller>) {
    controller->set_state(d.controller);  // a state-space controller's may exceed a Vector
    controller->set_previous_command(typename Controller::Vector(d.last_command.cast<Scalar>()));
  }
  return true;
}

}  // namespace flexloop::sim
