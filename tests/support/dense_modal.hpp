// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The compiled dense and modal plants side by side on the same seeded N(0,1) input: how far the
// modal form's outputs are from the dense form's (tests/runtime, tests/hard_cases).
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <random>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"

namespace flexloop::test {

/// max_k |y_dense - y_modal|_inf / max_k |y_dense|_inf over `steps` steps; also checks the final
/// states, |x_dense - T z| <= state_tolerance |x_dense|.
template <int NX, int NU, int NY>
double dense_modal_disagreement(const plant::lti::DiscreteStateSpace& d,
                                const plant::lti::ModalForm& m, int steps, double state_tolerance) {
  using plant::runtime::DensePlant;
  using plant::runtime::ModalPlant;
  auto dense = DensePlant<double, NX, NU, NY>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  auto modal = ModalPlant<double, NX, NU, NY>::from_modal_form(m);
  std::mt19937 rng(11);
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, NU, 1> u;
  double diff = 0, scale = 0;
  for (int k = 0; k < steps; ++k) {
    for (int i = 0; i < NU; ++i) u(i) = n01(rng);
    const auto y = dense.output(u);
    diff = std::max(diff, (y - modal.output(u)).cwiseAbs().maxCoeff());
    scale = std::max(scale, y.cwiseAbs().maxCoeff());
    dense.advance(u);
    modal.advance(u);
  }
  const double state_diff = (dense.state() - modal.physical_state()).cwiseAbs().maxCoeff();
  const double state_scale = dense.state().cwiseAbs().maxCoeff();
  INFO(std::scientific << "final state: |x_dense - T z| = " << state_diff
                       << ", |x| = " << state_scale);
  CHECK(state_diff <= state_tolerance * state_scale);
  return diff / scale;
}

}  // namespace flexloop::test
