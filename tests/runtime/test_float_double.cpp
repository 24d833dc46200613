// SPDX-License-Identifier: BSD-3-Clause
// float against double over 10^6 steps (100 s at 10 kHz) of the metrology plant, dense and modal,
// within the bound derived in tests/support/float_error_bound.hpp, evaluated for this plant and
// this run. (tests/hard_cases/test_float_long_run.cpp runs 10^8 steps.)
#include <catch2/catch.hpp>

#include <random>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/support/float_error_bound.hpp"
#include "tests/support/long_run.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using plant::runtime::DensePlant;
using plant::runtime::ModalPlant;

namespace {

constexpr long kSteps = test::long_run_steps(1000000);
constexpr int kNx = 12, kNu = 12, kNy = 12;

// Floor accelerations ~1e-3 m/s² RMS (the scene's level) and actuator forces ~1 N RMS.
struct SceneLevelInput {
  std::mt19937 rng{3};
  std::normal_distribution<double> n01;
  void operator()(long, Eigen::Matrix<double, kNu, 1>& u) {
    for (int i = 0; i < kNu; ++i) u(i) = (i < 6 ? 1e-3 : 1.0) * n01(rng);
  }
};

}  // namespace

TEST_CASE("float vs double: dense metrology plant, 10^6 steps, within the derived bound",
          "[runtime][float][metrology]") {
  const auto& s = test::metrology().s.plant.sys;
  const Eigen::MatrixXd Delta = s.A - Eigen::MatrixXd::Identity(kNx, kNx);
  const auto c = test::compare_float_double<DensePlant, kNx, kNu, kNy>(
      Delta, s.B, s.C, s.D, kSteps,
      [&](auto tag) { return decltype(tag)::type::from_matrices(s.A, s.B, s.C, s.D); },
      SceneLevelInput{});
  test::check_float_comparison(c);
}

TEST_CASE("float vs double: modal metrology plant, 10^6 steps, within the derived bound",
          "[runtime][float][metrology]") {
  const auto m = plant::lti::to_modal_form(test::metrology().s.plant);
  const auto c = test::compare_float_double<ModalPlant, kNx, kNu, kNy>(
      m.Lambda_minus_I, m.B, m.C, m.D, kSteps,
      [&](auto tag) { return decltype(tag)::type::from_modal_form(m); }, SceneLevelInput{});
  test::check_float_comparison(c);
}
