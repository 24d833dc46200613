// SPDX-License-Identifier: BSD-3-Clause
// The general (start-up-sized) plant against independent references: a dynamic-size plant
// stepped from its matrices with the held inputs fed back by hand ([w_k; h_{k-1}]), on sizes the
// runtime has no compiled path for (odd state counts, unequal channel counts, 200 states), and
// against the compiled DensePlant / ModalPlant on the metrology frame (same sample, same numbers
// up to the order of summation).
#include <catch2/catch.hpp>

#include <limits>

#include <random>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/general_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/support/discrete_systems.hpp"
#include "tests/support/dynamic_reference.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using plant::runtime::GeneralDensePlant;
using plant::runtime::GeneralModalPlant;

namespace {

// A stable plant of `pairs` lightly damped complex pole pairs and `reals` real poles.
plant::lti::DiscreteStateSpace test_plant(int pairs, int reals, Eigen::Index nu, Eigen::Index ny,
                                          unsigned seed) {
  std::vector<test::DiscretePole> poles;
  for (int i = 0; i < pairs; ++i) poles.push_back({0.999 - 1e-3 * i, 0.01 + 0.003 * i});
  for (int i = 0; i < reals; ++i) poles.push_back({0.9 - 0.05 * i, 0});
  return test::discrete_system(poles, nu, ny, seed);
}

// Largest |y_general - y_reference| / max |y_reference| over `steps` samples with random w and
// random held commands h.
template <class Plant>
double relative_error_to_reference(Plant plant, const plant::lti::DiscreteStateSpace& d,
                                   Eigen::Index held, int steps) {
  test::PlantReference ref{d.sys.A, d.sys.B, d.sys.C, d.sys.D};
  const Eigen::Index nu = d.sys.B.cols(), nw = nu - held;
  std::mt19937 rng(11);
  std::normal_distribution<double> n01;
  Eigen::VectorXd h_prev = Eigen::VectorXd::Zero(held);
  double err = 0, scale = 0;
  for (int k = 0; k < steps; ++k) {
    Eigen::VectorXd w(nw), h(held);
    for (auto& v : w) v = n01(rng);
    for (auto& v : h) v = n01(rng);
    Eigen::VectorXd u(nu);
    u << w, h_prev;
    const Eigen::VectorXd y_ref = ref.output(u);
    typename Plant::Input in(nu);
    in << w.cast<typename Plant::Input::Scalar>(), h.cast<typename Plant::Input::Scalar>();
    const auto& y = plant.output(in.head(nw));
    err = std::max(err, (y.template cast<double>() - y_ref).cwiseAbs().maxCoeff());
    scale = std::max(scale, y_ref.cwiseAbs().maxCoeff());
    plant.advance(in);
    u << w, h;
    ref.advance(u);
    h_prev = h;
  }
  return err / scale;
}

}  // namespace

TEST_CASE("general plant: sizes with no compiled path match a dynamic-size reference",
          "[runtime][general]") {
  struct Case {
    int pairs, reals;
    Eigen::Index nu, ny, held;
  };
  // Odd state counts (a real pole last), unequal channel counts, one held input of many, a
  // 200-state plant with 12 inputs and outputs.
  for (const Case c :
       {Case{1, 1, 2, 3, 1}, Case{3, 1, 5, 4, 2}, Case{2, 3, 9, 2, 8}, Case{100, 0, 12, 12, 6}}) {
    const auto d = test_plant(c.pairs, c.reals, c.nu, c.ny, 3);
    CAPTURE(d.sys.A.rows(), c.nu, c.ny, c.held);
    const auto dense =
        GeneralDensePlant<double>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D, c.held);
    CHECK(dense.states() == d.sys.A.rows());
    CHECK(dense.held_inputs() == c.held);
    // One step's sums of nx + nu terms round to within (nx + nu) eps, and the slowest pole keeps
    // an error for about 1 / (1 - radius) samples: the sum over the run is bounded by their
    // product (200 states: 4.7e-11; measured 1.0e-12 with the column-ordered sums, 2e-15 on the
    // small plants).
    const double dense_bound = static_cast<double>(d.sys.A.rows() + c.nu) *
                               std::numeric_limits<double>::epsilon() / (1 - d.spectral_radius);
    CHECK(relative_error_to_reference(dense, d, c.held, 3000) < dense_bound);
    const auto modal =
        GeneralModalPlant<double>::from_modal_form(plant::lti::to_modal_form(d), c.held);
    // The modal basis is well conditioned here (random S = I + 0.3 R): 1e-10 covers cond(T) eps
    // and the lightly damped poles' amplification.
    CHECK(relative_error_to_reference(modal, d, c.held, 3000) < 1e-10);
    const auto dense_float =
        GeneralDensePlant<float>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D, c.held);
    CHECK(relative_error_to_reference(dense_float, d, c.held, 3000) < 2e-3);
  }
}

TEST_CASE("general plant: the metrology frame steps as the compiled plant does",
          "[runtime][general]") {
  const auto& d = test::metrology().s.plant;
  using Dense = plant::runtime::DensePlant<double, 12, 12, 12, 6>;
  using Modal = plant::runtime::ModalPlant<double, 12, 12, 12, 6>;
  auto dense = Dense::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  auto general_dense =
      GeneralDensePlant<double>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D, 6);
  const auto form = plant::lti::to_modal_form(d);
  auto modal = Modal::from_modal_form(form);
  auto general_modal = GeneralModalPlant<double>::from_modal_form(form, 6);
  std::mt19937 rng(4);
  std::normal_distribution<double> n01;
  double dense_err = 0, modal_err = 0, scale = 0;
  for (int k = 0; k < 20000; ++k) {
    Eigen::Matrix<double, 12, 1> u;
    for (int i = 0; i < 6; ++i) u(i) = 1e-3 * n01(rng);
    for (int i = 6; i < 12; ++i) u(i) = n01(rng);
    const Eigen::Matrix<double, 12, 1> y = dense.output(u.head<6>());
    scale = std::max(scale, y.cwiseAbs().maxCoeff());
    dense_err = std::max(dense_err, (general_dense.output(u.head<6>()) - y).cwiseAbs().maxCoeff());
    modal_err = std::max(modal_err, (general_modal.output(u.head<6>()) -
                                     Eigen::Matrix<double, 12, 1>(modal.output(u.head<6>())))
                                        .cwiseAbs()
                                        .maxCoeff());
    dense.advance(u);
    general_dense.advance(u);
    modal.advance(u);
    general_modal.advance(u);
  }
  CHECK(dense_err / scale < 1e-13);
  CHECK(modal_err / scale < 1e-12);
  CHECK((general_modal.physical_state() - modal.physical_state()).norm() <=
        1e-11 * modal.physical_state().norm());
}

TEST_CASE("general plant: inconsistent sizes and non-finite entries are refused",
          "[runtime][general]") {
  const auto d = test_plant(1, 1, 4, 3, 5);
  const Eigen::MatrixXd& A = d.sys.A;
  CHECK_THROWS_WITH(
      GeneralDensePlant<double>::from_matrices(A, d.sys.B, d.sys.C.leftCols(2), d.sys.D, 2),
      Catch::Contains("C is 3x2, expected 3x3"));
  CHECK_THROWS_WITH(GeneralDensePlant<double>::from_matrices(A, d.sys.B, d.sys.C, d.sys.D, 4),
                    Catch::Contains("4 held inputs of 4"));
  Eigen::MatrixXd bad = A;
  bad(1, 2) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(GeneralDensePlant<double>::from_matrices(bad, d.sys.B, d.sys.C, d.sys.D, 2),
                    Catch::Contains("Ad(1,2) is not finite"));
  // Too many channels of one kind.
  const auto wide = test_plant(1, 0, 2 * numeric::kMaxChannels + 1, 2, 6);
  CHECK_THROWS_WITH(
      GeneralDensePlant<double>::from_matrices(wide.sys.A, wide.sys.B, wide.sys.C, wide.sys.D, 1),
      Catch::Contains("inputs; the runtime takes 2 .. 128"));
}
