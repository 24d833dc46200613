// DensePlant: the fixed-size step equals a dynamic-size reference, start-up refuses an artefact
// of the wrong size with a message naming both sizes, and the size dispatch finds the compiled
// sizes.
#include <catch2/catch.hpp>

#include <random>

#include "plant/runtime/runtime_sizes.hpp"
#include "tests/support/discrete_systems.hpp"
#include "tests/support/dynamic_reference.hpp"

using namespace flexloop;
using plant::runtime::DensePlant;

TEST_CASE("dense plant: output and advance equal a dynamic-size reference to rounding",
          "[runtime][dense]") {
  const auto d = test::discrete_system({{0.999, 0.05}, {0.99, 0.3}, {0.95, 0}, {1.0, 0}}, 3, 2, 7);
  auto plant = DensePlant<double, 6, 3, 2>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  test::PlantReference ref{d.sys.A, d.sys.B, d.sys.C, d.sys.D};
  std::mt19937 rng(1);
  std::normal_distribution<double> n01;
  double worst = 0, scale = 0;
  for (int k = 0; k < 1000; ++k) {
    Eigen::Vector3d u(n01(rng), n01(rng), n01(rng));
    const Eigen::Vector2d y = plant.output(u);
    const Eigen::VectorXd y_ref = ref.output(u);
    worst = std::max(worst, (y - y_ref).cwiseAbs().maxCoeff());
    scale = std::max(scale, y_ref.cwiseAbs().maxCoeff());
    plant.advance(u);
    ref.advance(u);
  }
  // Same products in a different summation order: a few ulps per step, 1000 steps of memory.
  CHECK(worst <= 1e-13 * scale);
  CHECK((plant.state() - ref.x).cwiseAbs().maxCoeff() <= 1e-13 * ref.x.cwiseAbs().maxCoeff());

  plant.reset();
  CHECK(plant.state().isZero(0));
  const Eigen::Matrix<double, 6, 1> x0 = Eigen::Matrix<double, 6, 1>::LinSpaced(1, 6);
  plant.set_state(x0);
  const Eigen::Vector3d u0(0.5, -1, 2);
  CHECK((plant.output(u0) - (d.sys.C * x0 + d.sys.D * u0)).norm() <= 1e-14 * 20);
}

TEST_CASE("dense plant: an artefact of another size is a start-up error naming both sizes",
          "[runtime][dense]") {
  const auto d = test::discrete_system({{0.9, 0.1}, {0.8, 0}}, 2, 2, 3);  // 3 states
  using Plant = DensePlant<double, 2, 2, 2>;
  CHECK_THROWS_WITH(Plant::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D),
                    Catch::Contains("DensePlant: Ad is 3x3, expected 2x2"));
  using Plant3 = DensePlant<double, 3, 1, 2>;
  CHECK_THROWS_WITH(Plant3::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D),
                    Catch::Contains("DensePlant: Bd is 3x2, expected 3x1"));
  Eigen::MatrixXd bad = d.sys.A;
  bad(1, 2) = std::nan("");
  using Plant32 = DensePlant<float, 3, 2, 2>;
  CHECK_THROWS_WITH(Plant32::from_matrices(bad, d.sys.B, d.sys.C, d.sys.D),
                    Catch::Contains("Ad(1,2) is not finite"));
  CHECK_NOTHROW(Plant32::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D));
}

TEST_CASE("runtime sizes: the dispatch finds each compiled size and lists them otherwise",
          "[runtime][sizes]") {
  const auto nx_of = [](long nx, long nu, long ny) {
    return plant::runtime::with_runtime_size(nx, nu, ny, [](auto size) {
      return decltype(size)::NX * 10000 + decltype(size)::NU * 100 + decltype(size)::NY;
    });
  };
  CHECK(nx_of(12, 12, 12) == 121212);
  CHECK(nx_of(24, 12, 12) == 241212);
  CHECK(nx_of(2, 2, 2) == 20202);
  CHECK_THROWS_WITH(nx_of(12, 12, 6), Catch::Contains("12 states, 12 inputs and 6 outputs") &&
                                          Catch::Contains("12/12/12 24/12/12 2/2/2"));
}
