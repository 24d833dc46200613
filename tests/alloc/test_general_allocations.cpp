// SPDX-License-Identifier: BSD-3-Clause
// No allocation inside a step on the general path (doc/design.md §6): the start-up-sized plant
// (dense and modal) with every simulated-hardware effect at start-up-sized channel counts (VC
// floor, lagged piezo, sensor chains on both output kinds, transport delay) and the general PI,
// 10^4 .. 10^5 closed-loop steps after a warm-up, at several sizes from 4 to 200 states and from
// 1 to 64 channels of a kind, counted by rt/counting_malloc.
#include <catch2/catch.hpp>

#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/state_space_controller.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/lti/vibration_criterion.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/piezo_actuator.hpp"
#include "plant/runtime/effects/sample_delay.hpp"
#include "plant/runtime/effects/sensor_chain.hpp"
#include "plant/runtime/general_plant.hpp"
#include "plant/runtime/simulated_hardware.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/discrete_systems.hpp"

using namespace flexloop;
namespace fx = plant::runtime::effects;
constexpr int kAny = Eigen::Dynamic;

namespace {

struct Size {
  int pairs;
  Eigen::Index disturbances, actuators, performance;
};

template <class Plant>
std::uint64_t closed_loop_allocations(Plant plant, const Size& n, long steps) {
  const Eigen::Index nc = n.actuators, nz = n.performance;
  const double dt = 1e-4;
  const auto filter =
      plant::lti::discretise_floor_filter(plant::lti::design_floor_filter(12.5e-6), dt);
  auto floor = fx::FloorGenerator<double, kAny, plant::lti::kFloorFilterOrder>::from_parameters(
      filter.sys.A, filter.sys.B, filter.sys.C, filter.sys.D, 1, fx::FloorStart::kStationary,
      n.disturbances);
  fx::PiezoActuatorParameters<kAny> piezo(nc);
  piezo.force_min.setConstant(-2);
  piezo.force_max.setConstant(2);
  piezo.lag_time_constant.setConstant(2e-4);
  fx::SensorParameters<kAny> sensor(nc), performance(nz);
  sensor.noise_rms.setConstant(1e-3);
  sensor.adc_range.setConstant(200);
  sensor.delay_samples = 1;
  performance.noise_rms.setConstant(1e-5);
  performance.adc_range.setConstant(1);
  performance.seed = 3;
  plant::runtime::SimulatedHardware<Plant, kAny, kAny, decltype(floor),
                                    fx::PiezoActuator<double, kAny, true>,
                                    fx::SensorChain<double, kAny>, fx::SensorChain<double, kAny>,
                                    fx::TransportDelay<double, kAny, kAny>, kAny>
      hw(std::move(plant), floor, fx::PiezoActuator<double, kAny, true>::from_parameters(piezo, dt),
         fx::SensorChain<double, kAny>::from_parameters(sensor),
         fx::SensorChain<double, kAny>::from_parameters(performance),
         fx::TransportDelay<double, kAny, kAny>::from_parameters(1, nc, nz), nc);
  artefact::PiParameters p;
  p.K_P = 2.0 * Eigen::MatrixXd::Identity(nc, nc);
  p.K_I = 100.0 * Eigen::MatrixXd::Identity(nc, nc);
  p.dt = dt;
  p.u_min = Eigen::VectorXd::Constant(1, -1.0);
  p.u_max = Eigen::VectorXd::Constant(1, 1.0);
  p.feedthrough_delay = 2;
  auto pi = controller::runtime::GeneralPiController<double>::from_parameters(p, nc);

  double sum = 0;
  const auto step = [&] {
    const auto& r = hw.sample();
    hw.apply(pi.step(r.sensors));
    sum += hw.performance()(0);
  };
  for (int k = 0; k < 1000; ++k) step();
  const std::uint64_t before = test::allocation_count();
  for (long k = 0; k < steps; ++k) step();
  const std::uint64_t after = test::allocation_count();
  REQUIRE(std::isfinite(sum));
  return after - before;
}

plant::lti::DiscreteStateSpace size_plant(const Size& n) {
  std::vector<test::DiscretePole> poles;
  for (int i = 0; i < n.pairs; ++i) poles.push_back({0.9995 - 1e-4 * (i % 7), 0.01 + 0.001 * i});
  return test::discrete_system(poles, n.disturbances + n.actuators, n.performance + n.actuators,
                               static_cast<unsigned>(n.pairs));
}

}  // namespace

TEST_CASE("allocation: the general path's closed loop allocates nothing at any size", "[alloc]") {
  for (const Size n :
       {Size{2, 1, 2, 3}, Size{6, 6, 6, 6}, Size{30, 64, 64, 64}, Size{100, 6, 12, 8}}) {
    const auto d = size_plant(n);
    CAPTURE(d.sys.A.rows(), n.disturbances, n.actuators, n.performance);
    const long steps = d.sys.A.rows() > 50 ? 10000 : 100000;
    CHECK(closed_loop_allocations(plant::runtime::GeneralDensePlant<double>::from_matrices(
                                      d.sys.A, d.sys.B, d.sys.C, d.sys.D, n.actuators),
                                  n, steps) == 0);
    CHECK(closed_loop_allocations(plant::runtime::GeneralModalPlant<double>::from_modal_form(
                                      plant::lti::to_modal_form(d), n.actuators),
                                  n, steps) == 0);
  }
}

TEST_CASE("allocation: the state-space controller's step allocates nothing", "[alloc]") {
  // 40 states, 8 sensors, 6 actuators, a coupled feedthrough with a delay, clamped commands with
  // both anti-windup policies (the hold branch and the update branch both run).
  const auto c = test::discrete_system({{0.9, 0.1}, {0.8, 0.3}, {0.7, 0}}, 8, 6, 17);
  for (const auto policy : {artefact::AntiWindup::kHold, artefact::AntiWindup::kNone}) {
    artefact::StateSpaceParameters p;
    p.A = Eigen::MatrixXd::Zero(40, 40);
    p.A.topLeftCorner(5, 5) = c.sys.A;
    p.A.bottomRightCorner(35, 35) = 0.5 * Eigen::MatrixXd::Identity(35, 35);
    p.B = Eigen::MatrixXd::Constant(40, 8, 0.01);
    p.B.topRows(5) = c.sys.B;
    p.C = Eigen::MatrixXd::Constant(6, 40, 0.1);
    p.D = 0.1 * Eigen::MatrixXd::Ones(6, 8);
    p.dt = 1e-4;
    p.feedthrough = 0.2 * Eigen::MatrixXd::Ones(8, 6);
    p.feedthrough_delay = 2;
    p.u_min = Eigen::VectorXd::Constant(1, -0.5);
    p.u_max = Eigen::VectorXd::Constant(1, 0.5);
    p.anti_windup = policy;
    auto controller = controller::runtime::StateSpaceController<double>::from_parameters(p);
    controller::runtime::StateSpaceController<double>::Vector y(8);
    double sum = 0;
    const auto step = [&](long k) {
      for (Eigen::Index i = 0; i < 8; ++i)
        y(i) = std::sin(0.001 * static_cast<double>(k * (i + 1)));
      sum += controller.step(y)(0);
    };
    for (long k = 0; k < 1000; ++k) step(k);
    const std::uint64_t before = test::allocation_count();
    for (long k = 0; k < 100000; ++k) step(k);
    CHECK(test::allocation_count() - before == 0);
    CHECK(std::isfinite(sum));
  }
}
