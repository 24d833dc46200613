// SPDX-License-Identifier: BSD-3-Clause
// No allocation inside a step (doc/design.md §6): 10^6 closed-loop steps of the metrology plant
// with the PI controller, after a warm-up, in every plant form and scalar, with the allocation
// functions of this executable replaced by counting ones (rt/counting_malloc). First the
// counter is shown to see operator new, malloc and an Eigen dynamic-size temporary.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <random>
#include <type_traits>

#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/closed_loop.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;

namespace {

// Keeps the optimiser from removing an allocation whose result is unused.
template <typename T>
void escape(T* p) {
  asm volatile("" : : "g"(p) : "memory");
}

constexpr int kSteps = 1000000;
constexpr int kWarmUp = 1000;

template <typename Loop>
std::uint64_t allocations_in_steps(Loop& loop) {
  using W = typename Loop::Disturbance;
  // Floor accelerations drawn before counting: 4096 samples, reused cyclically.
  std::mt19937 rng(5);
  std::normal_distribution<float> n01;
  std::vector<W> w(4096);
  for (auto& v : w)
    for (int i = 0; i < W::RowsAtCompileTime; ++i) v(i) = 1e-3f * n01(rng);
  typename Loop::Output sum = Loop::Output::Zero();
  for (int k = 0; k < kWarmUp; ++k) sum += loop.step(w[k & 4095]);
  const std::uint64_t before = test::allocation_count();
  for (int k = 0; k < kSteps; ++k) sum += loop.step(w[k & 4095]);
  const std::uint64_t after = test::allocation_count();
  REQUIRE(sum.allFinite());
  return after - before;
}

template <typename Scalar, template <typename, int, int, int, int> class Plant>
Plant<Scalar, 12, 12, 12, 6> metrology_plant() {
  const auto& d = test::metrology().s.plant;
  if constexpr (std::is_same_v<Plant<Scalar, 12, 12, 12, 6>,
                               plant::runtime::DensePlant<Scalar, 12, 12, 12, 6>>)
    return Plant<Scalar, 12, 12, 12, 6>::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
  else
    return Plant<Scalar, 12, 12, 12, 6>::from_modal_form(plant::lti::to_modal_form(d));
}

template <typename Scalar, template <typename, int, int, int, int> class Plant>
std::uint64_t metrology_loop_allocations() {
  auto params = test::metrology_pi_parameters();
  // ±2 N: about 2 % of the samples saturate, so the anti-windup path runs too.
  params.u_min = Eigen::VectorXd::Constant(1, -2.0);
  params.u_max = Eigen::VectorXd::Constant(1, 2.0);
  using Pi = controller::runtime::PiController<Scalar, 6>;
  test::ClosedLoop<Plant<Scalar, 12, 12, 12, 6>, Pi, 6> loop(metrology_plant<Scalar, Plant>(),
                                                             Pi::from_parameters(params));
  return allocations_in_steps(loop);
}

}  // namespace

TEST_CASE("allocation counter: counts operator new, malloc and Eigen dynamic temporaries",
          "[alloc]") {
  // Every count is taken before any CHECK: the reporter may allocate.
  const std::uint64_t c0 = test::allocation_count();
  int* i = new int(3);
  escape(i);
  delete i;
  const std::uint64_t c1 = test::allocation_count();
  void* p = std::malloc(64);
  escape(p);
  std::free(p);
  const std::uint64_t c2 = test::allocation_count();
  {
    Eigen::VectorXd v = Eigen::VectorXd::Ones(50);
    escape(v.data());
  }
  const std::uint64_t c3 = test::allocation_count();
  CHECK(c1 - c0 == 1);
  CHECK(c2 - c1 == 1);
  CHECK(c3 - c2 == 1);
}

TEST_CASE("allocation: 10^6 closed-loop steps (plant + PI) allocate nothing", "[alloc]") {
  test::metrology();  // build the scene (allocates) before any counting
  CHECK(metrology_loop_allocations<double, plant::runtime::DensePlant>() == 0);
  CHECK(metrology_loop_allocations<float, plant::runtime::DensePlant>() == 0);
  CHECK(metrology_loop_allocations<double, plant::runtime::ModalPlant>() == 0);
  CHECK(metrology_loop_allocations<float, plant::runtime::ModalPlant>() == 0);
}
