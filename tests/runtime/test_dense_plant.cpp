// SPDX-License-Identifier: BSD-3-Clause
// DensePlant: the fixed-size step equals a dynamic-size reference, start-up refuses an artefact
// of the wrong size with a message naming both sizes, and the size dispatch finds the compiled
// sizes.
#include <catch2/catch.hpp>

#include <random>

#include "plant/runtime/compiled_loops.hpp"
#include "plant/runtime/dense_plant.hpp"
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

TEST_CASE("compiled loops: the dispatch finds each entry of the typed list, and nothing else",
          "[runtime][sizes]") {
  using plant::runtime::LoopCounts;
  using plant::runtime::PlantForm;
  // A number that names the entry: states, each channel count and the form.
  const auto id_of = [](const LoopCounts& n) {
    return plant::runtime::with_compiled_loop(
        n,
        [](auto loop) {
          using L = decltype(loop);
          return L::NX * 100000 + L::NW * 10000 + L::NC * 1000 + L::NZ * 100 + L::NS * 10 +
                 (L::kForm == PlantForm::kModal ? 1 : 0);
        },
        [] { return -1; });
  };
  const LoopCounts metrology{.states = 12,
                             .disturbances = 6,
                             .actuators = 6,
                             .performance = 6,
                             .sensors = 6,
                             .form = PlantForm::kDense};
  CHECK(id_of(metrology) == 1266660);
  LoopCounts modal = metrology;
  modal.form = PlantForm::kModal;
  CHECK(id_of(modal) == 1266661);
  LoopCounts preloaded = metrology;
  preloaded.states = 24;
  CHECK(id_of(preloaded) == 2466660);
  // Any count that differs from every entry goes to the general path.
  for (auto LoopCounts::*count :
       {&LoopCounts::states, &LoopCounts::disturbances, &LoopCounts::actuators,
        &LoopCounts::performance, &LoopCounts::sensors}) {
    LoopCounts other = metrology;
    other.*count += 1;
    CHECK(id_of(other) == -1);
  }
  LoopCounts preloaded_modal = preloaded;  // no compiled modal loop for it: the general path
  preloaded_modal.form = PlantForm::kModal;
  CHECK(id_of(preloaded_modal) == -1);
  // What a controller sees: its actuator and sensor counts.
  const auto channels_of = [](Eigen::Index nc, Eigen::Index ns) {
    return plant::runtime::with_compiled_channels(
        nc, ns, [](auto loop) { return decltype(loop)::NC; }, [] { return -1; });
  };
  CHECK(channels_of(6, 6) == 6);
  CHECK(channels_of(6, 5) == -1);
  CHECK(channels_of(2, 2) == -1);
}
