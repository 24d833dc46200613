// SPDX-License-Identifier: BSD-3-Clause
// Held inputs (plant/runtime/state_output.hpp): a plant whose last NH inputs are held from one
// advance() to the next gives, in the sampled loop's order, the output a plant without held inputs
// gives for the input [w_k; h_{k-1}]: y_k = C x_k + D [w_k; h_{k-1}], checked against a
// dynamic-size reference for the dense and the modal form, double and float. set_state() keeps
// the held inputs, reset() clears them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/support/discrete_systems.hpp"
#include "tests/support/dynamic_reference.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using plant::runtime::DensePlant;
using plant::runtime::ModalPlant;

namespace {

// max_k |y_k - y_ref,k|_inf / max_k |y_ref,k|_inf over `steps` samples of the loop
//   y_k = plant.output(w_k),  plant.advance([w_k; h_k])
// against the reference fed [w_k; h_{k-1}] at the output and [w_k; h_k] at the advance; w and h
// seeded N(0,1). Also checks that held() is h_k after each advance.
template <typename Plant>
double held_disagreement(Plant& plant, test::PlantReference ref, int steps) {
  constexpr int NU = Plant::Input::RowsAtCompileTime, NH = Plant::kHeldInputs,
                NS = Plant::kSampledInputs;
  using Scalar = typename Plant::Input::Scalar;
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(NU);  // [w_k; h_{k-1}], then [w_k; h_k]
  double diff = 0, scale = 0;
  bool held_kept = true;
  for (int k = 0; k < steps; ++k) {
    for (int i = 0; i < NS; ++i) u(i) = n01(rng);
    const Eigen::VectorXd y_ref = ref.output(u);
    const Eigen::VectorXd y =
        plant.output(u.template head<NS>().template cast<Scalar>()).template cast<double>();
    diff = std::max(diff, (y - y_ref).cwiseAbs().maxCoeff());
    scale = std::max(scale, y_ref.cwiseAbs().maxCoeff());
    for (int i = NS; i < NU; ++i) u(i) = n01(rng);
    plant.advance(u.cast<Scalar>());
    ref.advance(u);
    held_kept = held_kept && plant.held().template cast<double>() ==
                                 u.tail(NH).template cast<Scalar>().template cast<double>();
  }
  CHECK(held_kept);
  return diff / scale;
}

}  // namespace

TEST_CASE(
    "held inputs: dense and modal metrology plant give C x + D [w, h_prev] of a dynamic-size "
    "reference to rounding over 10^4 samples",
    "[runtime][dense][modal][held][metrology]") {
  const auto& d = test::metrology().s.plant;
  const auto m = plant::lti::to_modal_form(d);
  const test::PlantReference dense_ref{d.sys.A, d.sys.B, d.sys.C, d.sys.D};
  const test::PlantReference modal_ref{m.Lambda, m.B, m.C, m.D};

  auto dense = DensePlant<double, 12, 12, 12, 6>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  auto modal = ModalPlant<double, 12, 12, 12, 6>::from_modal_form(m);
  const double dense_rel = held_disagreement(dense, dense_ref, 10000);
  const double modal_rel = held_disagreement(modal, modal_ref, 10000);
  // float: the same loop, against the double reference (float rounding of the matrices and sums).
  auto dense_f =
      DensePlant<float, 12, 12, 12, 6>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  const double dense_f_rel = held_disagreement(dense_f, dense_ref, 10000);
  INFO(std::scientific << "dense " << dense_rel << ", modal " << modal_rel << ", dense float "
                       << dense_f_rel);
  // Same products in other summation orders (and C Bd + D_h rounded once): measured 6e-15 dense,
  // 5e-14 modal (its reference steps Λ itself, not Λ - I), 2.4e-6 = 40 float epsilons in float.
  CHECK(dense_rel <= 1e-13);
  CHECK(modal_rel <= 1e-12);
  CHECK(dense_f_rel <= 2e-5);
}

TEST_CASE(
    "held inputs: a small plant with 2 of 3 inputs held, set_state keeps the held inputs and reset "
    "clears them",
    "[runtime][dense][held]") {
  const auto d = test::discrete_system({{0.999, 0.05}, {0.99, 0.3}, {0.95, 0}, {1.0, 0}}, 3, 2, 7);
  using Plant = DensePlant<double, 6, 3, 2, 2>;
  auto plant = Plant::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  CHECK(held_disagreement(plant, {d.sys.A, d.sys.B, d.sys.C, d.sys.D}, 1000) <= 1e-13);

  // Held h = (-1, 2) from this advance on; then a state set from outside.
  plant.advance(Eigen::Vector3d(0.3, -1, 2));
  const Eigen::Matrix<double, 6, 1> x0 = Eigen::Matrix<double, 6, 1>::LinSpaced(1, 6);
  plant.set_state(x0);
  const Eigen::Matrix<double, 1, 1> w0(0.5);
  const Eigen::VectorXd expected = d.sys.C * x0 + d.sys.D * Eigen::Vector3d(0.5, -1, 2);
  CHECK((plant.output(w0) - expected).cwiseAbs().maxCoeff() <=
        1e-14 * expected.cwiseAbs().maxCoeff());
  plant.reset();
  CHECK(plant.held().isZero(0));
  const Eigen::VectorXd only_w = d.sys.D.leftCols(1) * w0;
  CHECK((plant.output(w0) - only_w).cwiseAbs().maxCoeff() <= 1e-15 * only_w.norm());
}
