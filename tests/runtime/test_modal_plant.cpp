// SPDX-License-Identifier: BSD-3-Clause
// The modal (real block-diagonal) plant against the dense one, in double: the same outputs to
// 1e-12 relative over 10^5 steps for a plant with an exactly repeated pair, real poles and
// repeated integrator poles at z = 1, and for the metrology frame (its 13.9/13.9 Hz and 31.3/31.3
// Hz pairs are exact). A defective Ad (double integrator) is refused, pointing to the dense form.
#include <catch2/catch.hpp>

#include <algorithm>
#include <functional>
#include <random>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/support/dense_modal.hpp"
#include "tests/support/discrete_systems.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using plant::runtime::DensePlant;
using plant::runtime::ModalPlant;

using test::dense_modal_disagreement;

TEST_CASE(
    "modal form: repeated pair, real poles and integrators, dense and modal agree to 1e-11 "
    "over 10^5 steps",
    "[runtime][modal]") {
  // z = 0.9995 e^{±j0.0087} twice (exact repeated pair, like 13.9 Hz at 10 kHz), a distinct pair,
  // two real poles, and z = 1 twice (integrators).
  const auto d = test::discrete_system(
      {{0.9995, 0.0087}, {0.9995, 0.0087}, {0.999, 0.03}, {0.9, 0}, {0.5, 0}, {1.0, 0}, {1.0, 0}},
      3, 4, 5);
  const auto m = plant::lti::to_modal_form(d);
  // Two 2x2 blocks for the repeated pair, one for the other pair, 1x1 blocks for 0.9 and 0.5; the
  // integrators at z = 1 come as two 1x1 blocks or, split by rounding into a pair with a
  // negligible imaginary part, one 2x2 block. Either way 10 states.
  int states = 0;
  for (int b : m.block_sizes) states += b;
  CHECK(states == 10);
  CHECK(std::count(m.block_sizes.begin(), m.block_sizes.end(), 2) >= 3);
  // The pairs come first, so every 2x2 block starts at an even index (the runtime needs it).
  CHECK(std::is_sorted(m.block_sizes.begin(), m.block_sizes.end(), std::greater<>()));
  CHECK(m.eigenvector_condition < 1e3);
  // Λ is T^-1 Ad T to rounding.
  CHECK((d.sys.A * m.T - m.T * m.Lambda).norm() <= 1e-13 * d.sys.A.norm() * m.T.norm());

  // The integrators at z = 1 remember everything: a pole offset of a few eps between the two
  // forms (neither can hold the other's exactly) grows into a difference ~ k eps, 1e-11 at
  // k = 10^5, in the states and so in the outputs they feed (measured 1e-12 or so, depending on
  // whether the build fuses multiply-adds). The metrology plant below, without a double
  // integrator, agrees to 1e-12.
  const double rel = dense_modal_disagreement<10, 3, 4>(d, m, 100000, 1e-11);
  INFO(std::scientific << "relative disagreement " << rel);
  CHECK(rel <= 1e-11);
}

TEST_CASE("modal form: the metrology plant, dense and modal agree to 1e-12 over 10^5 steps",
          "[runtime][modal][metrology]") {
  const auto& d = test::metrology().s.plant;
  const auto m = plant::lti::to_modal_form(d);
  INFO("cond(T) = " << m.eigenvector_condition);
  CHECK(m.block_sizes == std::vector<int>(6, 2));
  CHECK(m.eigenvector_condition < 1e4);
  const double rel = dense_modal_disagreement<12, 12, 12>(d, m, 100000, 1e-12);
  INFO(std::scientific << "relative disagreement " << rel);
  CHECK(rel <= 1e-12);
}

TEST_CASE(
    "modal form: a defective Ad (double integrator) is refused with a pointer to the dense "
    "form",
    "[runtime][modal]") {
  plant::lti::DiscreteStateSpace d{};
  const double T = 1e-4;
  d.sys.A = (Eigen::MatrixXd(3, 3) << 1, T, 0, 0, 1, 0, 0, 0, 0.5).finished();
  d.sys.B = Eigen::MatrixXd::Ones(3, 1);
  d.sys.C = Eigen::MatrixXd::Ones(1, 3);
  d.sys.D = Eigen::MatrixXd::Zero(1, 1);
  d.sys.states = {"p", "v", "x"};
  d.sys.inputs = {"a"};
  d.sys.outputs = {"y"};
  d.dt = T;
  CHECK_THROWS_WITH(plant::lti::to_modal_form(d),
                    Catch::Contains("defective") && Catch::Contains("use the dense form"));
}

TEST_CASE("modal plant: start-up refuses a Lambda that is not real block-diagonal",
          "[runtime][modal]") {
  using Plant = ModalPlant<double, 3, 1, 1>;
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(3, 1), C = Eigen::MatrixXd::Ones(1, 3),
                        D = Eigen::MatrixXd::Zero(1, 1), T = Eigen::MatrixXd::Identity(3, 3);
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(3, 3);
  L << 0.9, 0.1, 0, -0.1, 0.9, 0, 0, 0, 0.5;
  CHECK_NOTHROW(Plant::from_modal_form(L, B, C, D, T));
  Eigen::MatrixXd coupled = L;
  coupled(0, 2) = 0.01;
  CHECK_THROWS_WITH(Plant::from_modal_form(coupled, B, C, D, T),
                    Catch::Contains("not real block-diagonal"));
  Eigen::MatrixXd skew = L;
  skew(1, 0) = -0.2;
  CHECK_THROWS_WITH(Plant::from_modal_form(skew, B, C, D, T),
                    Catch::Contains("not of the form [[a, b], [-b, a]]"));
  Eigen::MatrixXd real_first = Eigen::MatrixXd::Zero(3, 3);
  real_first << 0.5, 0, 0, 0, 0.9, 0.1, 0, -0.1, 0.9;
  CHECK_THROWS_WITH(Plant::from_modal_form(real_first, B, C, D, T),
                    Catch::Contains("starts at an odd index"));
  CHECK_THROWS_WITH(Plant::from_modal_form(L, Eigen::MatrixXd::Ones(3, 2), C, D, T),
                    Catch::Contains("Bm is 3x2, expected 3x1"));
}

TEST_CASE(
    "modal form: the metrology frame under gravity preload (24 states, double integrators of the "
    "floor motion) builds modal: the floor's Jordan blocks beside the structure's modes, dense and "
    "modal agree",
    "[runtime][modal][metrology][preload]") {
  auto sc = scene::load_scene(test::metrology_scene_path());
  sc.gravity_preload = true;
  const auto d = scene::sample_scene(scene::build_scene_plant(sc)).plant;
  REQUIRE(d.sys.nx() == 24);
  const auto m = plant::lti::to_modal_form(d);
  // The structure's six pairs, then the floor's six blocks [[0, t], [0, 0]].
  CHECK(m.block_sizes == std::vector<int>(12, 2));
  for (int c = 0; c < 6; ++c) {
    const int k = 12 + 2 * c;
    CHECK(m.Lambda_minus_I(k, k) == 0);
    CHECK(m.Lambda_minus_I(k, k + 1) == d.dt);
    CHECK(m.Lambda_minus_I(k + 1, k) == 0);
  }
  // Random inputs drive the floor's integrators: the state grows as a random walk, the outputs
  // (accelerations, forces) do not.
  const double rel = dense_modal_disagreement<24, 12, 12>(d, m, 100000, 1e-9);
  INFO(std::scientific << "relative disagreement " << rel);
  CHECK(rel <= 1e-9);
}

TEST_CASE(
    "modal form: the shipped flexible arm (106 states, three floor points, slow beam modes) "
    "builds modal, and dense and modal agree",
    "[runtime][modal][arm]") {
  const auto d = scene::sample_scene(
                     scene::build_scene_plant(scene::load_scene("tools/scenes/flexible_arm.toml")))
                     .plant;
  REQUIRE(d.sys.nx() == 106);
  const auto m = plant::lti::to_modal_form(d);
  const double rel = dense_modal_disagreement<106, 5, 4>(d, m, 20000, 1e-7);
  INFO(std::scientific << "relative disagreement " << rel);
  CHECK(rel <= 1e-7);
}

namespace {

// max over `steps` steps of |output(u) - (C state + D u)|_inf / |y|_inf: the C x the plant keeps
// (computed in advance() from the previous state, plant/runtime/state_output.hpp) against C times
// the state it now holds.
template <typename Plant>
double kept_output_disagreement(Plant& plant, const Eigen::MatrixXd& C, const Eigen::MatrixXd& D,
                                int steps) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  typename Plant::Input u;
  double diff = 0, scale = 0;
  for (int k = 0; k < steps; ++k) {
    for (int i = 0; i < u.size(); ++i) u(i) = n01(rng);
    const Eigen::VectorXd direct = C * plant.state() + D * u;
    diff = std::max(diff, (plant.output(u) - direct).cwiseAbs().maxCoeff());
    scale = std::max(scale, direct.cwiseAbs().maxCoeff());
    plant.advance(u);
  }
  return diff / scale;
}

}  // namespace

TEST_CASE(
    "dense and modal plant: the output's C x, kept with the state, is C times the state to "
    "rounding, after every step and after set_state",
    "[runtime][dense][modal][metrology]") {
  const auto& d = test::metrology().s.plant;
  const auto m = plant::lti::to_modal_form(d);
  auto dense = DensePlant<double, 12, 12, 12>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  auto modal = ModalPlant<double, 12, 12, 12>::from_modal_form(m);
  // (C Ad) x + (C Bd) u against C (x + (Ad - I) x + Bd u): different sums of the same terms.
  const double dense_rel = kept_output_disagreement(dense, d.sys.C, d.sys.D, 10000);
  const double modal_rel = kept_output_disagreement(modal, m.C, m.D, 10000);
  INFO(std::scientific << "dense " << dense_rel << ", modal " << modal_rel);
  CHECK(dense_rel <= 1e-13);
  CHECK(modal_rel <= 1e-13);

  const Eigen::Matrix<double, 12, 1> x0 = Eigen::Matrix<double, 12, 1>::LinSpaced(-1, 2);
  const Eigen::Matrix<double, 12, 1> u0 = Eigen::Matrix<double, 12, 1>::LinSpaced(3, -1);
  modal.set_state(x0);
  const Eigen::VectorXd expected = m.C * x0 + m.D * u0;
  CHECK((modal.output(u0) - expected).cwiseAbs().maxCoeff() <=
        1e-14 * expected.cwiseAbs().maxCoeff());
  modal.reset();
  CHECK((modal.output(u0) - m.D * u0).cwiseAbs().maxCoeff() <= 1e-14 * (m.D * u0).norm());
}
