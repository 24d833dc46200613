// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The simulation loop of a plant with inputs [w; u] (NW disturbances, then actuator commands) and
// outputs [z; y] (performance outputs, then the sensors the controller reads), closed by a
// controller whose command is held for one sample (as in plant::lti::close_loop_sampled):
//
//   y_k = Cd x_k + Dd [w_k; u_{k-1}]      (the sensors see the command still held)
//   u_k = controller.step(sensor part of y_k)
//   x_{k+1} = Ad x_k + Bd [w_k; u_k]
//
// The plant holds the command itself (its last NU - NW inputs are held inputs,
// plant/runtime/state_output.hpp): output() takes w_k only. step(w) returns the whole output y_k.
// Fixed-size, allocation-free.
#include <Eigen/Core>

namespace flexloop::test {

template <typename Plant, typename Controller, int NW>
class ClosedLoop {
 public:
  using Input = typename Plant::Input;
  using Output = typename Plant::Output;
  using Disturbance = Eigen::Matrix<typename Input::Scalar, NW, 1>;
  static constexpr int kNu = Input::RowsAtCompileTime - NW;
  static constexpr int kNy = Controller::Vector::RowsAtCompileTime;
  static_assert(Plant::kHeldInputs == kNu, "the plant must hold the controller's commands");

  ClosedLoop(Plant plant, Controller controller) : plant_(plant), controller_(controller) {}

  Output step(const Disturbance& w) noexcept {
    in_.template head<NW>() = w;
    const Output y = plant_.output(w);  // with u_{k-1}, held in the plant
    in_.template tail<kNu>() = controller_.step(y.template tail<kNy>());
    plant_.advance(in_);
    return y;
  }

  Plant& plant() noexcept { return plant_; }
  Controller& controller() noexcept { return controller_; }

 private:
  Plant plant_;
  Controller controller_;
  Input in_ = Input::Zero();
};

}  // namespace flexloop::test
