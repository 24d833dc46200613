// SPDX-License-Identifier: BSD-3-Clause
// Disk margins of the sampled loop (controller/design/disk_margins.hpp). References the code under
// test did not produce: a first-order loop whose sensitivity is written out by hand and scanned
// on a fine grid, its exact gain margin, and the loop's own poles (sampled_loop_stability) with
// the actuator gain moved to the edges of the guaranteed range and beyond.
#include <catch2/catch.hpp>

#include <cmath>
#include <complex>

#include "controller/design/disk_margins.hpp"
#include "controller/design/sampled_loop_stability.hpp"
#include "offline/scene/scene_plant.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;

namespace {

constexpr double kA = 0.95, kB = 0.2, kK = 2.0, kDt = 1e-3;

// x+ = a x + b u (the command held over the sample), y = x; the controller u = -k y, no states.
plant::lti::DiscreteStateSpace first_order_plant() {
  plant::lti::DiscreteStateSpace g{
      {}, kDt, plant::lti::DiscretisationMethod::kZeroOrderHold, 0, kA};
  g.sys.A = Eigen::MatrixXd::Constant(1, 1, kA);
  g.sys.B = Eigen::MatrixXd::Constant(1, 1, kB);
  g.sys.C = Eigen::MatrixXd::Identity(1, 1);
  g.sys.D = Eigen::MatrixXd::Zero(1, 1);
  g.sys.states = {"x"};
  g.sys.inputs = {"u"};
  g.sys.outputs = {"y"};
  return g;
}

// first_order_plant beside a 50 Hz resonance damped 0.05 % (rotation form), both seen in y.
plant::lti::DiscreteStateSpace lightly_damped_plant() {
  plant::lti::DiscreteStateSpace g = first_order_plant();
  const double theta = 2 * M_PI * 50 * kDt, r = std::exp(-0.0005 * 2 * M_PI * 50 * kDt);
  g.sys.A = Eigen::MatrixXd::Zero(3, 3);
  g.sys.A(0, 0) = kA;
  g.sys.A.bottomRightCorner(2, 2) << r * std::cos(theta), r * std::sin(theta), -r * std::sin(theta),
      r * std::cos(theta);
  g.sys.B = Eigen::MatrixXd::Zero(3, 1);
  g.sys.B(0, 0) = kB;
  g.sys.B(1, 0) = 3e-5;
  g.sys.C = Eigen::MatrixXd::Zero(1, 3);
  g.sys.C(0, 0) = g.sys.C(0, 1) = 1;
  g.sys.states = {"x", "r1", "r2"};
  return g;
}

plant::lti::DiscreteStateSpace proportional(double k) {
  plant::lti::DiscreteStateSpace c{{}, kDt, plant::lti::DiscretisationMethod::kZeroOrderHold, 0, 0};
  c.sys.A = Eigen::MatrixXd::Zero(0, 0);
  c.sys.B = Eigen::MatrixXd::Zero(0, 1);
  c.sys.C = Eigen::MatrixXd::Zero(1, 0);
  c.sys.D = Eigen::MatrixXd::Constant(1, 1, -k);
  c.sys.inputs = {"y"};
  c.sys.outputs = {"u"};
  return c;
}

controller::design::SampledLoopHardware no_feedthrough() {
  controller::design::SampledLoopHardware hw;
  hw.removed_feedthrough = Eigen::MatrixXd::Zero(1, 1);
  return hw;
}

}  // namespace

TEST_CASE("disk margin of a first-order sampled loop matches its sensitivity written out") {
  const auto loop = controller::design::sampled_loop_model(first_order_plant(), proportional(kK),
                                                           no_feedthrough());
  const auto m = controller::design::input_disk_margins(loop);
  // S(z) = 1 / (1 + L), L = k b / (z - a), scanned on a fine linear grid up to Nyquist.
  double peak = 0, at = 0;
  for (int i = 0; i <= 200'000; ++i) {
    const double f = 0.5 / kDt * i / 200'000.0;
    const std::complex<double> z = std::polar(1.0, 2 * M_PI * f * kDt);
    const std::complex<double> S = (z - kA) / (z - kA + kK * kB);
    if (std::abs(S - 0.5) > peak) peak = std::abs(S - 0.5), at = f;
  }
  REQUIRE(m.loops.size() == 1);
  CHECK(m.loops[0].alpha == Approx(1 / peak).epsilon(1e-8));
  CHECK(m.all_loops.alpha == Approx(1 / peak).epsilon(1e-8));
  CHECK(m.loops[0].frequency_hz == Approx(at).margin(0.5 / kDt / 200'000.0));
  // The exact gain margin: the pole a - f k b leaves the circle at f = (1 + a) / (k b). The
  // disk's range is inside it (a disk margin is a guarantee, not the limit).
  CHECK(m.loops[0].gain_high <= (1 + kA) / (kK * kB));
  CHECK(m.loops[0].gain_high >= 0.5 * (1 + kA) / (kK * kB));
  const auto d = controller::design::disk_margin_of(m.loops[0].alpha);
  CHECK(d.gain_low * d.gain_high == Approx(1.0));  // balanced: symmetric in dB
  CHECK(d.phase_deg == Approx(2 * std::atan(m.loops[0].alpha / 2) * 180 / M_PI));
}

TEST_CASE(
    "disk margins of the metrology frame's PI: the loop is stable across the guaranteed "
    "gain range") {
  const auto& p = test::metrology().p;
  const auto m = controller::design::input_disk_margins(scene::sampled_loop_model(p));
  REQUIRE(m.loops.size() == 6);
  REQUIRE(m.all_loops.alpha > 0);
  for (const auto& l : m.loops) {
    CHECK(l.alpha >= m.all_loops.alpha * (1 - 1e-9));  // one loop at a time tolerates more
    CHECK(l.frequency_hz > 0);
    CHECK(l.frequency_hz <= 0.5 * p.scene.discretisation.rate_hz);
  }
  // Every actuator's gain moved by the same factor: one of the perturbations the all-loops disk
  // covers. Inside the range the loop's poles stay inside the circle.
  const double rate = p.scene.discretisation.rate_hz;
  auto stable_with_gain = [&](double factor) {
    scene::SampledLoop s = scene::sampled_loop(p);
    s.hardware.actuator_gain *= factor;
    const auto g22 = plant::lti::discretise(
        p.feedback_path,
        {p.scene.discretisation.method, 1.0 / rate, p.scene.discretisation.prewarp_hz, false});
    return controller::design::sampled_loop_stability(g22, p.gains, s.hardware).stable();
  };
  CHECK(stable_with_gain(m.all_loops.gain_low * 1.001));
  if (std::isfinite(m.all_loops.gain_high)) CHECK(stable_with_gain(m.all_loops.gain_high * 0.999));
}

TEST_CASE(
    "disk margins: the default grid (with the loop's pole frequencies) finds the margins a "
    "30 000-point grid finds, for the metrology frame and a lightly damped loop") {
  const auto check_against_dense = [](const controller::design::SampledLoopModel& loop) {
    const auto m = controller::design::input_disk_margins(loop);
    const auto dense = controller::design::input_disk_margins(loop, {30'000});
    REQUIRE(m.loops.size() == dense.loops.size());
    for (std::size_t i = 0; i < m.loops.size(); ++i) {
      CHECK(m.loops[i].alpha == Approx(dense.loops[i].alpha).epsilon(1e-9));
      CHECK(m.loops[i].frequency_hz == Approx(dense.loops[i].frequency_hz).epsilon(1e-6));
    }
    CHECK(m.all_loops.alpha == Approx(dense.all_loops.alpha).epsilon(1e-9));
  };
  check_against_dense(scene::sampled_loop_model(test::metrology().p));
  // A first-order plant beside a resonance damped 0.05 %: its peak is narrower than the default
  // grid's spacing.
  check_against_dense(controller::design::sampled_loop_model(lightly_damped_plant(),
                                                             proportional(kK), no_feedthrough()));
}
