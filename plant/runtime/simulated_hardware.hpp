#pragma once
// The plant side of the loop: the discrete plant with the simulated hardware around it, composed
// at compile time from the effects a scene asks for (DESIGN.md §6, issue 6). An absent effect is
// the type NoEffect: it is not stored, not stepped, not even tested for at run time
// (`if constexpr`), so a scene without effects compiles to the bare plant loop.
//
// One sample period [k, k+1), in the order of the real-time loop
// (plant/lti/feedback_interconnection.hpp):
//   sample():   w_k = floor.step()                                 floor acceleration
//               [z; s] = plant.output(w_k)   with f_held, the actuator force since k-1, which
//                                             the plant holds (its last NC inputs are held inputs)
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
  static_assert(Plant::kHeldInputs == NC, "the plant holds the actuator forces between samples");
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
    in_.template head<NW>() = floor_.step();  // the tail holds the actuator force since k-1
    const auto out = plant_.output(in_.template head<NW>());
    z_ = out.template head<NZ>();
    // Straight into the reading: with no effect present this is all a sample does.
    reading_.force = out.template tail<NC>();
    reading_.accel = z_;
    if constexpr (kPresent<ForceSensor>) reading_.force = force_sensor_.step(reading_.force);
    if constexpr (kPresent<Accelerometer>) reading_.accel = accelerometer_.step(reading_.accel);
    if constexpr (kPresent<Transport>) {
      Eigen::Matrix<Scalar, NC + NZ, 1> packed;
      packed << reading_.force, reading_.accel;
      packed = transport_.step(packed);
      reading_.force = packed.template head<NC>();
      reading_.accel = packed.template tail<NZ>();
    }
    return reading_;
  }

  /// The controller's command for [k, k+1): through the actuator, then the plant advances.
  void apply(const Command& u) noexcept {
    if constexpr (kPresent<Actuator>)
      in_.template tail<NC>() = actuator_.step(u);
    else
      in_.template tail<NC>() = u;
    plant_.advance(in_);
  }

  const Performance& frame_acceleration() const noexcept { return z_; }
  Disturbance floor_acceleration() const noexcept { return in_.template head<NW>(); }
  /// The force the actuators hold over the current period.
  Command actuator_force() const noexcept { return in_.template tail<NC>(); }
  const Actuator& actuator() const noexcept { return actuator_; }
  const Plant& plant() const noexcept { return plant_; }

 private:
  Plant plant_;
  Floor floor_;
  [[no_unique_address]] Actuator actuator_;
  [[no_unique_address]] ForceSensor force_sensor_;
  [[no_unique_address]] Accelerometer accelerometer_;
  [[no_unique_address]] Transport transport_;
  typename Plant::Input in_ = Plant::Input::Zero();  // [floor; actuator force held]
  Performance z_ = Performance::Zero();
  Reading reading_{Command::Zero(), Performance::Zero()};
};

}  // namespace flexloop::plant::runtime
