// SPDX-License-Identifier: BSD-3-Clause
// Hard case 8 (doc/design.md §9): float over 10^8 steps (2.8 hours of the machine at 10 kHz). The
// metrology plant in modal form, float beside double on the same input, on a thread set up as a
// real-time loop thread is (denormals flushed to zero, rt/denormals.hpp). The error of the float
// outputs stays within the bound derived in tests/support/float_error_bound.hpp (worst-case
// rounding model, Higham §3), evaluated for this plant and this run: rounding errors do not
// accumulate beyond what the plant's own damping lets them, however long the run.
//
// And a decaying pole closer to the unit circle than float resolves is refused when a float modal
// or dense plant starts, in both the compiled and the general form, as is one whose decay float
// changes by more than 10 % (plant/runtime/pole_precision.hpp).
//
// The input: scene-level floor accelerations and forces for the first half, then nothing, so the
// second half is the free decay of a lightly damped plant towards rest, where the states pass
// through the subnormal range of float (below 1.2e-38) unless flushed.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/general_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "rt/denormals.hpp"
#include "tests/support/float_error_bound.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;

namespace {

constexpr long kSteps = 100'000'000;
constexpr int kNx = 12, kNu = 12, kNy = 12;

struct DrivenThenFree {
  std::mt19937 rng{5};
  std::normal_distribution<double> n01;
  void operator()(long k, Eigen::Matrix<double, kNu, 1>& u) {
    if (k >= kSteps / 2) {
      u.setZero();
      return;
    }
    for (int i = 0; i < kNu; ++i) u(i) = (i < 6 ? 1e-3 : 1.0) * n01(rng);
  }
};

}  // namespace

TEST_CASE("float vs double over 10^8 steps with denormals flushed: within the derived bound",
          "[hard][float][long_run]") {
  const auto m = plant::lti::to_modal_form(test::metrology().s.plant);
  test::FloatComparison c;
  bool flushed = false;
  const auto start = std::chrono::steady_clock::now();
  std::thread loop([&] {
    flushed = rt::flush_denormals_to_zero().ok && rt::denormals_flushed();
    c = test::compare_float_double<plant::runtime::ModalPlant, kNx, kNu, kNy>(
        m.Lambda_minus_I, m.B, m.C, m.D, kSteps,
        [&](auto tag) { return decltype(tag)::type::from_modal_form(m); }, DrivenThenFree{});
  });
  loop.join();
  WARN("10^8 steps of float and double side by side in "
       << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
  CHECK(flushed);
  test::check_float_comparison(c);
}

TEST_CASE("a decaying pole that float would put on the unit circle is refused at start-up",
          "[hard][float]") {
  // A fast, almost undamped pole z = 1 + a ± jb inside the circle by 1e-12 relative in b, with
  // b chosen so that rounding it to float lands on or beyond the circle. Scan angles until the
  // float neighbour of b lies above the circle (about every other angle does).
  double a = 0, b = 0;
  for (double theta = 0.5; theta < 0.6; theta += 1e-3) {
    a = static_cast<float>(std::cos(theta) - 1);  // exact in float and in double
    const double on_circle = std::sqrt(-(2 * a + a * a));
    b = on_circle * (1 - 1e-12);
    if (static_cast<double>(static_cast<float>(b)) >= on_circle) break;
  }
  REQUIRE(plant::runtime::pole_margin<double>(a, b).exact < 0);
  REQUIRE(plant::runtime::pole_margin<float>(a, b).stored >= 0);
  const Eigen::Matrix2d L = (Eigen::Matrix2d() << a, b, -b, a).finished();
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(2, 2), C = Eigen::MatrixXd::Ones(1, 2),
                        D = Eigen::MatrixXd::Zero(1, 2), T = Eigen::MatrixXd::Identity(2, 2);
  using Float = plant::runtime::ModalPlant<float, 2, 2, 1>;
  const char* kRefused = "float puts it on or outside the unit circle";
  using Double = plant::runtime::ModalPlant<double, 2, 2, 1>;
  CHECK_THROWS_WITH(Float::from_modal_form(L, B, C, D, T), Catch::Contains(kRefused));
  CHECK_NOTHROW(Double::from_modal_form(L, B, C, D, T));
  CHECK_THROWS_WITH(plant::runtime::GeneralModalPlant<float>::from_modal_form(L, B, C, D, T, 1),
                    Catch::Contains(kRefused));
  CHECK_NOTHROW(plant::runtime::GeneralModalPlant<double>::from_modal_form(L, B, C, D, T, 1));
  // The dense plants store Ad - I = L in float: the same pole, the same refusal.
  const Eigen::MatrixXd Ad = Eigen::Matrix2d::Identity() + L;
  using DenseFloat = plant::runtime::DensePlant<float, 2, 2, 1>;
  CHECK_THROWS_WITH(DenseFloat::from_matrices(Ad, B, C, D), Catch::Contains(kRefused));
  CHECK_NOTHROW(plant::runtime::DensePlant<double, 2, 2, 1>::from_matrices(Ad, B, C, D));
  CHECK_THROWS_WITH(plant::runtime::GeneralDensePlant<float>::from_matrices(Ad, B, C, D, 1),
                    Catch::Contains(kRefused));
  CHECK_NOTHROW(plant::runtime::GeneralDensePlant<double>::from_matrices(Ad, B, C, D, 1));
  // 0.99 L is well inside (|z|^2 - 1 = 0.02 a): float keeps it.
  const Eigen::MatrixXd inside = Eigen::Matrix2d::Identity() + 0.99 * L;
  CHECK_NOTHROW(DenseFloat::from_matrices(inside, B, C, D));
  // The metrology plant keeps every pole inside in float (the 10^8-step run above uses it).
  const auto m = plant::lti::to_modal_form(test::metrology().s.plant);
  CHECK_NOTHROW(plant::runtime::ModalPlant<float, kNx, kNu, kNy>::from_modal_form(m));
  const auto& d = test::metrology().s.plant.sys;
  CHECK_NOTHROW(
      plant::runtime::DensePlant<float, kNx, kNu, kNy>::from_matrices(d.A, d.B, d.C, d.D));
}

namespace {

// A fast, lightly damped pole z = 1 + a ± jb whose stored float b lies just inside the circle and
// whose exact b is chosen so that float's m = |z|^2 - 1 is `ratio` times double's: float stays
// inside but decays `ratio` - 1 faster.
Eigen::Matrix2d pole_with_float_decay_ratio(double ratio) {
  const double a = static_cast<float>(std::cos(0.5) - 1);  // exact in float and in double
  const double on_circle = std::sqrt(-(2 * a + a * a));
  float stored_b = static_cast<float>(on_circle);
  if (stored_b >= on_circle) stored_b = std::nextafter(stored_b, 0.0f);
  const double stored_m = 2 * a + a * a + double(stored_b) * stored_b;
  const double b = std::sqrt(stored_m / ratio - 2 * a - a * a);
  return (Eigen::Matrix2d() << a, b, -b, a).finished();
}

}  // namespace

TEST_CASE("a pole whose decay float changes by more than 10 % is refused at start-up",
          "[hard][float]") {
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(2, 2), C = Eigen::MatrixXd::Ones(1, 2),
                        D = Eigen::MatrixXd::Zero(1, 2), T = Eigen::MatrixXd::Identity(2, 2);
  const char* kRefused = "float changes its decay by 50";
  const Eigen::Matrix2d L = pole_with_float_decay_ratio(1.5);
  const auto margin = plant::runtime::pole_margin<float>(L(0, 0), L(0, 1));
  REQUIRE(margin.stored < 0);
  REQUIRE(margin.decay_change() == Approx(0.5).epsilon(1e-6));
  using Float = plant::runtime::ModalPlant<float, 2, 2, 1>;
  CHECK_THROWS_WITH(Float::from_modal_form(L, B, C, D, T), Catch::Contains(kRefused));
  CHECK_THROWS_WITH(plant::runtime::GeneralModalPlant<float>::from_modal_form(L, B, C, D, T, 1),
                    Catch::Contains(kRefused));
  CHECK_NOTHROW(plant::runtime::ModalPlant<double, 2, 2, 1>::from_modal_form(L, B, C, D, T));
  const Eigen::MatrixXd Ad = Eigen::Matrix2d::Identity() + L;
  using DenseFloat = plant::runtime::DensePlant<float, 2, 2, 1>;
  CHECK_THROWS_WITH(DenseFloat::from_matrices(Ad, B, C, D), Catch::Contains("float changes"));
  CHECK_THROWS_WITH(plant::runtime::GeneralDensePlant<float>::from_matrices(Ad, B, C, D, 1),
                    Catch::Contains("float changes"));
  // 5 % is within the tolerance: kept, both forms.
  const Eigen::Matrix2d near = pole_with_float_decay_ratio(1.05);
  REQUIRE(plant::runtime::pole_margin<float>(near(0, 0), near(0, 1)).decay_change() ==
          Approx(0.05).epsilon(1e-4));
  CHECK_NOTHROW(Float::from_modal_form(near, B, C, D, T));
  CHECK_NOTHROW(DenseFloat::from_matrices(Eigen::Matrix2d::Identity() + near, B, C, D));
}
