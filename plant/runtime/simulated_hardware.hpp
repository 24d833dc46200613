// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant side of the loop: the discrete plant with the simulated hardware around it, composed
// from the effects a scene asks for (doc/design.md §6, issue 6). Each slot is an effect type: an
// absent effect is the type NoEffect, not stored, not stepped, not even tested for at run time
// (`if constexpr`), so a scene without effects compiles to the bare plant loop; a slot may also be
// an EffectChoice (effect_choice.hpp), whose effect is chosen at start-up, for the loops that
// online/sim/loop_hardware.hpp does not compose at compile time.
//
// One sample period [k, k+1), in the order of the real-time loop
// (plant/lti/feedback_interconnection.hpp):
//   sample():   w_k = floor.step()                                 floor acceleration
//               [z; s] = plant.output(w_k)   with f_held, the actuator force since k-1, which
//                                             the plant holds (its last NC inputs are held inputs)
//               sensors_k = SensorChain(s),  performance_k = PerformanceChain(z)
//               (sensors_k, performance_k) -> Transport delay -> what the controller receives
//   apply(u_k): f_k = Actuator(u_k)  (ideal: f_k = u_k)
//               plant.advance([w_k; f_k]),  f_held = f_k
// The performance output z (true frame acceleration, before the sensors) is kept for scoring.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "numeric/channel_limits.hpp"

namespace flexloop::plant::runtime {

/// An effect slot the scene leaves empty.
struct NoEffect {};

template <class T>
inline constexpr bool kPresent = !std::is_same_v<T, NoEffect>;

/// NW disturbances (the floor), NC actuators, NS sensors; the plant's outputs are the performance
/// signals (NZ = outputs - NS) then the sensors. Compiled counts, or Eigen::Dynamic for counts set
/// at start-up (the general path: the constructor's `sensors` then says NS).
template <class Plant, int NW, int NC, class Floor, class Actuator = NoEffect,
          class SensorChain = NoEffect, class PerformanceChain = NoEffect,
          class Transport = NoEffect, int NS = NC>
class SimulatedHardware {
 public:
  using Scalar = typename Plant::Output::Scalar;
  static constexpr int NY = Plant::Output::RowsAtCompileTime;
  static constexpr int NZ = NY == Eigen::Dynamic || NS == Eigen::Dynamic ? Eigen::Dynamic : NY - NS;
  static_assert(NY == Eigen::Dynamic || NZ > 0, "outputs: performance signals, then sensors");
  using Disturbance = numeric::ChannelsOf<Scalar, NW>;
  using Command = numeric::ChannelsOf<Scalar, NC>;
  using Sensors = numeric::ChannelsOf<Scalar, NS>;
  using Performance = numeric::ChannelsOf<Scalar, NZ>;
  struct Reading {
    Sensors sensors;          ///< what the sensors read (e.g. strut forces [N])
    Performance performance;  ///< what the performance sensors read (e.g. accelerations [m/s^2])
  };

  /// @throws std::invalid_argument when the plant's held inputs are not the NC actuators, or the
  /// counts do not close (inputs = disturbances + actuators, outputs = performance + sensors).
  SimulatedHardware(Plant plant, Floor floor, Actuator actuator = {}, SensorChain sensor = {},
                    PerformanceChain performance = {}, Transport transport = {},
                    Eigen::Index sensors = NS)
      : plant_(std::move(plant)),
        floor_(std::move(floor)),
        actuator_(std::move(actuator)),
        sensor_chain_(std::move(sensor)),
        performance_chain_(std::move(performance)),
        transport_(std::move(transport)) {
    const Eigen::Index nu = plant_.inputs(), nc = plant_.held_inputs(), nw = nu - nc,
                       ny = plant_.outputs(), nz = ny - sensors;
    const auto require = [](bool ok, const std::string& what) {
      if (!ok) throw std::invalid_argument("simulated hardware: " + what);
    };
    require(NC == Eigen::Dynamic || nc == NC, "the plant holds " + std::to_string(nc) +
                                                  " inputs, expected the " + std::to_string(NC) +
                                                  " actuators");
    require(NW == Eigen::Dynamic || nw == NW,
            "the plant samples " + std::to_string(nw) + " inputs, expected " + std::to_string(NW));
    require(nc >= 1 && nc <= numeric::kMaxChannels && nw >= 1 && nw <= numeric::kMaxChannels &&
                sensors >= 1 && sensors <= numeric::kMaxChannels && nz >= 1 &&
                nz <= numeric::kMaxChannels,
            std::to_string(nw) + " disturbances, " + std::to_string(nc) + " actuators, " +
                std::to_string(nz) + " performance outputs and " + std::to_string(sensors) +
                " sensors; each count must be 1 .. " + std::to_string(numeric::kMaxChannels));
    in_ = Plant::Input::Zero(nu);
    z_ = Performance::Zero(nz);
    reading_.sensors = Sensors::Zero(sensors);
    reading_.performance = Performance::Zero(nz);
  }

  /// The sample at instant k: what the sensors read (after the transport delay, if any).
  [[gnu::flatten]] const Reading& sample() noexcept {
    const Eigen::Index nw = floor_channels(), nz = z_.size(), ns = reading_.sensors.size();
    in_.template head<NW>(nw) = floor_.step();  // the tail holds the actuator force since k-1
    const auto& out = plant_.output(in_.template head<NW>(nw));
    z_ = out.template head<NZ>(nz);
    // Straight into the reading: with no effect present this is all a sample does.
    // segment<N>(start, n), not tail<N>(n): Eigen 3.4's tail<Dynamic>(n) does not compile.
    reading_.sensors = out.template segment<NS>(out.size() - ns, ns);
    reading_.performance = z_;
    if constexpr (kPresent<SensorChain>) reading_.sensors = sensor_chain_.step(reading_.sensors);
    if constexpr (kPresent<PerformanceChain>)
      reading_.performance = performance_chain_.step(reading_.performance);
    if constexpr (kPresent<Transport>) {
      reading_.sensors = transport_.sensors.step(reading_.sensors);
      reading_.performance = transport_.performance.step(reading_.performance);
    }
    return reading_;
  }

  /// The controller's command for [k, k+1): through the actuator, then the plant advances.
  template <typename U>
  [[gnu::flatten]] void apply(const Eigen::MatrixBase<U>& u) noexcept {
    const Eigen::Index nw = floor_channels(), nc = in_.size() - nw;
    if constexpr (kPresent<Actuator>)
      in_.template segment<NC>(nw, nc) = actuator_.step(u);
    else
      in_.template segment<NC>(nw, nc) = u;
    plant_.advance(in_);
  }

  /// A run's start (artefact/loop_start.hpp): the plant's state in its own coordinates, the
  /// actuator force held since the last sample and, for an actuator with a lag, the lag's force.
  void start_at(const typename Plant::State& x, const Command& held, const Command& lag) noexcept {
    plant_.set_state(x, held);
    in_.template segment<NC>(floor_channels(), held.size()) = held;
    if constexpr (kPresent<Actuator>) {
      if constexpr (requires { actuator_.visit([](auto&) {}); })
        actuator_.visit([&lag](auto& effect) { effect.set_lag_state(lag); });
      else
        actuator_.set_lag_state(lag);
    }
  }
  /// A run's start: the sensor delay line, then the transport's, filled with what the sensor
  /// chain gave before the delay, q(j) at sample k - j (j = 1 .. sensor + transport delay).
  template <class Past>
  void start_sensor_lines(const Past& q) noexcept {
    int sensor_delay = 0;
    if constexpr (kPresent<SensorChain>) {
      const auto fill = [&](auto& chain) {
        sensor_delay = chain.delay();
        for (int j = 1; j <= sensor_delay; ++j) chain.set_past(j, q(j));
      };
      if constexpr (requires { sensor_chain_.visit(fill); })
        sensor_chain_.visit(fill);
      else
        fill(sensor_chain_);
    }
    if constexpr (kPresent<Transport>)
      for (int j = 1; j <= transport_.sensors.delay(); ++j)
        transport_.sensors.set_past(j, q(j + sensor_delay));
  }

  /// The floor generator (its state, for a start drawn given it).
  const Floor& floor() const noexcept { return floor_; }

  /// The true performance outputs of the last sample (before the performance sensors).
  const Performance& performance() const noexcept { return z_; }
  /// The disturbances of the last sample (the floor accelerations).
  auto floor_acceleration() const noexcept { return in_.template head<NW>(floor_channels()); }
  /// The force the actuators hold over the current period.
  auto actuator_force() const noexcept {
    return in_.template segment<NC>(floor_channels(), in_.size() - floor_channels());
  }
  const Actuator& actuator() const noexcept { return actuator_; }
  const Plant& plant() const noexcept { return plant_; }

  Eigen::Index disturbances() const noexcept { return floor_channels(); }
  Eigen::Index actuators() const noexcept { return in_.size() - floor_channels(); }
  Eigen::Index performance_outputs() const noexcept { return z_.size(); }
  Eigen::Index sensors() const noexcept { return reading_.sensors.size(); }

 private:
  Eigen::Index floor_channels() const noexcept {
    if constexpr (NW == Eigen::Dynamic)
      return in_.size() - plant_.held_inputs();
    else
      return NW;
  }

  Plant plant_;
  Floor floor_;
  [[no_unique_address]] Actuator actuator_;
  [[no_unique_address]] SensorChain sensor_chain_;
  [[no_unique_address]] PerformanceChain performance_chain_;
  [[no_unique_address]] Transport transport_;
  typename Plant::Input in_;  // [floor; actuator force held]
  Performance z_;
  Reading reading_;
};

}  // namespace flexloop::plant::runtime
