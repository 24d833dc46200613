#pragma once
// The plant side of the loop: the discrete plant with the simulated hardware around it, composed
// at compile time from the effects a scene asks for (DESIGN.md §6, issue 6). An absent effect is
// the type NoEffect: it is not stored, not stepped, not even tested for at run time
// (`if constexpr`), so a scene without effects compiles to the bare plant loop.
//
// One sample period [k, k+1), in the order of the real-time loop
// (plant/lti/feedback_interconnection.hpp):
//   sample():   w_k = floor.step()                                 floor acceleration
//               [z; s] = plant.output([w_k; f_held])               f_held: actuator force since k-1
//               force_k = ForceSensor(s),  accel_k = Accelerometer(z)
//               (force_k, accel_k) -> Transport delay -> what the controller receives
//   apply(u_k): f_k = Actuator(u_k)  (ideal: f_k = u_k)
//               plant.advance([w_k; f_k]),  f_held = f_k
// The performance output z (true frame acceleration, before the sensors) is kept for scoring.
#include <Eigen/Core>
#include <type_traits>
#include <utility>

namespace flexloop::plant::runtime {

/// An effect slot the scene leaves empty.
struct NoEffect {};

template <class T>
inline constexpr bool kPresent = !std::is_same_v<T, NoEffect>;

template <class Plant, int NW, int NC, class Floor, class Actuator = NoEffect,
          class ForceSensor = NoEffect, class Accelerometer = NoEffect, class Transport = NoEffect>
class SimulatedHardware {
 public:
  using Scalar = typename Plant::Output::Scalar;
  static constexpr int NY = Plant::Output::RowsAtCompileTime, NZ = NY - NC;
  static_assert(Plant::Input::RowsAtCompileTime == NW + NC, "inputs: floor, then actuators");
  static_assert(NZ > 0, "outputs: frame accelerations, then force sensors");
  using Disturbance = Eigen::Matrix<Scalar, NW, 1>;
  using Command = Eigen::Matrix<Scalar, NC, 1>;
  using Performance = Eigen::Matrix<Scalar, NZ, 1>;
  struct Reading {
    Command force;      ///< force sensors [N]
    Performance accel;  ///< accelerometers [m/s^2]
  };

  SimulatedHardware(Plant plant, Floor floor, Actuator actuator = {}, ForceSensor force = {},
                    Accelerometer accel = {}, Transport transport = {})
      : plant_(std::move(plant)),
        floor_(std::move(floor)),
        actuator_(std::move(actuator)),
        force_sensor_(std::move(force)),
        accelerometer_(std::move(accel)),
        transport_(std::move(transport)) {}

  /// The sample at instant k: what the sensors read (after the transport delay, if any).
  const Reading& sample() noexcept {
    in_.template head<NW>() = floor_.step();
    in_.template tail<NC>() = force_held_;
    const auto out = plant_.output(in_);
    z_ = out.template head<NZ>();
    Command force = out.template tail<NC>();
    Performance accel = z_;
    if constexpr (kPresent<ForceSensor>) force = force_sensor_.step(force);
    if constexpr (kPresent<Accelerometer>) accel = accelerometer_.step(accel);
    if constexpr (kPresent<Transport>) {
      Eigen::Matrix<Scalar, NC + NZ, 1> packed;
      packed << force, accel;
      packed = transport_.step(packed);
      force = packed.template head<NC>();
      accel = packed.template tail<NZ>();
    }
    reading_.force = force;
    reading_.accel = accel;
    return reading_;
  }

  /// The controller's command for [k, k+1): through the actuator, then the plant advances.
  void apply(const Command& u) noexcept {
    if constexpr (kPresent<Actuator>)
      force_held_ = actuator_.step(u);
    else
      force_held_ = u;
    in_.template tail<NC>() = force_held_;
    plant_.advance(in_);
  }

  const Performance& frame_acceleration() const noexcept { return z_; }
  Disturbance floor_acceleration() const noexcept { return in_.template head<NW>(); }
  const Command& actuator_force() const noexcept { return force_held_; }
  const Actuator& actuator() const noexcept { return actuator_; }
  const Plant& plant() const noexcept { return plant_; }

 private:
  Plant plant_;
  Floor floor_;
  [[no_unique_address]] Actuator actuator_;
  [[no_unique_address]] ForceSensor force_sensor_;
  [[no_unique_address]] Accelerometer accelerometer_;
  [[no_unique_address]] Transport transport_;
  typename Plant::Input in_ = Plant::Input::Zero();
  Command force_held_ = Command::Zero();
  Performance z_ = Performance::Zero();
  Reading reading_{Command::Zero(), Performance::Zero()};
};

}  // namespace flexloop::plant::runtime
