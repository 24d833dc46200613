// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The study's runs on the online kernels (offline/study/tradeoff.hpp): a plant (compiled or
// general path, any form and scalar) with a controller, fed with floor samples given in advance, so
// that the loop does nothing the configuration would not do in `flexloop sim` but the plant, the
// controller and the copy of the floor sample.
#include <Eigen/Core>

namespace flexloop::study {

/// A zero command for a loop without a controller (open loop).
template <typename Scalar>
struct ZeroCommand {
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> u;
  template <typename Y>
  const auto& step(const Eigen::MatrixBase<Y>&) noexcept {
    return u;
  }
};

/// `steps` closed-loop samples: w (disturbances x samples, in the plant's scalar; taken in turn,
/// from the first again when steps exceed them) -> plant output -> controller on the last `ns`
/// outputs -> plant advance with [w; u]. z (when given, nz x steps): the first nz outputs. NW, NS:
/// the disturbance and sensor counts of a compiled loop, Eigen::Dynamic on the general path.
template <int NW, int NS, class Plant, class Controller, class W>
void run_loop(Plant& plant, Controller& controller, const W& w, Eigen::Index nz, Eigen::Index ns,
              long steps, Eigen::MatrixXd* z) {
  using Scalar = typename W::Scalar;
  const Eigen::Index nw = w.rows(), nc = plant.held_inputs();
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> in =
      Eigen::Matrix<Scalar, Eigen::Dynamic, 1>::Zero(nw + nc);
  for (long k = 0, col = 0; k < steps; ++k, col = col + 1 == w.cols() ? 0 : col + 1) {
    in.template head<NW>(nw) = w.col(col);
    const auto& y = plant.output(in.template head<NW>(nw));
    if (z) z->col(k) = y.head(nz).template cast<double>();
    in.tail(nc) = controller.step(y.template segment<NS>(y.size() - ns, ns));
    plant.advance(in);
  }
}

/// `steps` open-loop samples with every input at 1 from the first; y: outputs x steps.
template <int NW, class Plant>
Eigen::MatrixXd unit_step(Plant& plant, Eigen::Index nw, long steps) {
  const Eigen::Index nc = plant.held_inputs();
  const typename Plant::Input in = Plant::Input::Ones(nw + nc);
  Eigen::MatrixXd y(plant.outputs(), steps);
  for (long k = 0; k < steps; ++k) {
    y.col(k) = plant.output(in.template head<NW>(nw)).template cast<double>();
    plant.advance(in);
  }
  return y;
}

}  // namespace flexloop::study
