// SPDX-License-Identifier: BSD-3-Clause
// The state-space controller (controller/runtime/state_space_controller.hpp), a user's own design
// of any size: against plant::lti::close_loop_sampled (the offline model of the sampled loop, an
// independent formula) with sensors and actuators of different counts, a coupled feedthrough D22
// and a direct term; against the PI force feedback it generalises; its anti-windup policies,
// bumpless start, feedthrough delay and start-up refusals.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "controller/design/sampled_loop_stability.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/loop_controller.hpp"
#include "controller/runtime/state_space_controller.hpp"
#include "plant/lti/feedback_interconnection.hpp"
#include "tests/support/discrete_systems.hpp"

using namespace flexloop;
using artefact::AntiWindup;
using artefact::StateSpaceParameters;
using Catch::Matchers::Contains;
using controller::runtime::StateSpaceController;

static_assert(controller::runtime::LoopController<StateSpaceController<double>>);
static_assert(
    controller::runtime::LoopController<controller::runtime::GeneralPiController<double>>);

namespace {

// A plant of nw disturbances, nc actuators, nz performance outputs, ns sensors, and a controller
// of nxc states for it; small gains keep the loop bounded over the test's samples.
struct Loop {
  plant::lti::DiscreteStateSpace plant, controller;
  Eigen::Index nw, nc, nz, ns;
};

Loop random_loop(Eigen::Index nw, Eigen::Index nc, Eigen::Index nz, Eigen::Index ns,
                 unsigned seed) {
  Loop l{test::discrete_system({{0.99, 0.05}, {0.95, 0.2}, {0.9, 0}}, nw + nc, nz + ns, seed),
         test::discrete_system({{0.8, 0.1}, {0.7, 0}}, ns, nc, seed + 1),
         nw,
         nc,
         nz,
         ns};
  l.controller.sys.C *= 0.1;
  l.controller.sys.D *= 0.2;
  l.plant.sys.D.bottomRightCorner(ns, nc) *= 0.5;  // D22: coupled, not the identity
  return l;
}

StateSpaceParameters parameters(const Loop& l) {
  StateSpaceParameters p;
  p.A = l.controller.sys.A;
  p.B = l.controller.sys.B;
  p.C = l.controller.sys.C;
  p.D = l.controller.sys.D;
  p.dt = l.controller.dt;
  p.feedthrough = l.plant.sys.D.bottomRightCorner(l.ns, l.nc);
  return p;
}

}  // namespace

TEST_CASE("the state-space controller closes the loop exactly as close_loop_sampled models it",
          "[controller][state_space]") {
  const Eigen::Index nw = 2, nc = 3, nz = 2, ns = 4;
  const Loop l = random_loop(nw, nc, nz, ns, 7);
  const auto closed = plant::lti::close_loop_sampled(l.plant, l.controller, {nw, nz});
  auto c = StateSpaceController<double>::from_parameters(parameters(l));
  REQUIRE(c.sensors() == ns);
  REQUIRE(c.actuators() == nc);
  REQUIRE(c.states() == l.controller.sys.nx());

  const auto& P = l.plant.sys;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(P.nx()), u_held = Eigen::VectorXd::Zero(nc);
  Eigen::VectorXd X = Eigen::VectorXd::Zero(closed.sys.nx());
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  double worst = 0, largest = 0;
  for (int k = 0; k < 2000; ++k) {
    Eigen::VectorXd w(nw);
    for (auto& v : w) v = n01(rng);
    // The loop as the runtime runs it: the sensors hold the previous command.
    const Eigen::VectorXd y = P.C.bottomRows(ns) * x + P.D.bottomLeftCorner(ns, nw) * w +
                              P.D.bottomRightCorner(ns, nc) * u_held;
    const Eigen::VectorXd z =
        P.C.topRows(nz) * x + P.D.topLeftCorner(nz, nw) * w + P.D.topRightCorner(nz, nc) * u_held;
    const Eigen::VectorXd u = c.step(y);
    x = P.A * x + P.B.leftCols(nw) * w + P.B.rightCols(nc) * u;
    u_held = u;
    // The offline model of that loop.
    const Eigen::VectorXd z_ref = closed.sys.C * X + closed.sys.D * w;
    X = closed.sys.A * X + closed.sys.B * w;
    worst = std::max(worst, (z - z_ref).cwiseAbs().maxCoeff());
    largest = std::max(largest, z_ref.cwiseAbs().maxCoeff());
  }
  CAPTURE(worst, largest);
  REQUIRE(largest > 0.1);  // the loop was excited
  CHECK(worst <= 1e-12 * largest);
}

TEST_CASE("the PI force feedback as a state space commands what the PI controller does",
          "[controller][state_space]") {
  const Eigen::Index n = 5;
  std::mt19937 rng(11);
  artefact::PiParameters pi;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  pi.K_P = 4.0 * I + 0.3 * test::random_matrix(rng, n, n);
  pi.K_I = 150.0 * (I + 0.1 * test::random_matrix(rng, n, n));
  pi.feedthrough = I + 0.05 * test::random_matrix(rng, n, n);
  pi.dt = 1e-4;
  pi.leak_rad_s = 2.0;
  for (const int delay : {0, 2}) {
    CAPTURE(delay);
    pi.feedthrough_delay = delay;
    controller::design::PiGains gains;
    gains.K_P = pi.K_P;
    gains.K_I = pi.K_I;
    gains.settings.leak_rad_s = pi.leak_rad_s;
    const auto d = controller::design::pi_discrete_controller(gains, pi.dt);
    StateSpaceParameters p;
    p.A = d.sys.A;
    p.B = d.sys.B;
    p.C = d.sys.C;
    p.D = d.sys.D;
    p.dt = pi.dt;
    p.feedthrough = pi.feedthrough;
    p.feedthrough_delay = delay;
    auto a = controller::runtime::GeneralPiController<double>::from_parameters(pi, n);
    auto b = StateSpaceController<double>::from_parameters(p);
    std::normal_distribution<double> n01;
    double worst = 0, largest = 0;
    for (int k = 0; k < 5000; ++k) {
      Eigen::VectorXd y(n);
      for (auto& v : y) v = n01(rng);
      const Eigen::VectorXd ua = a.step(y), ub = b.step(y);
      worst = std::max(worst, (ua - ub).cwiseAbs().maxCoeff());
      largest = std::max(largest, ua.cwiseAbs().maxCoeff());
    }
    CAPTURE(worst, largest);
    CHECK(worst <= 1e-11 * largest);
  }
}

TEST_CASE("anti-windup: hold keeps the state while a command is clamped, none runs on",
          "[controller][state_space]") {
  // An integrator: x+ = x + dt y, u = 100 x (one channel).
  StateSpaceParameters p;
  p.A = Eigen::MatrixXd::Identity(1, 1);
  p.B = Eigen::MatrixXd::Constant(1, 1, 1e-3);
  p.C = Eigen::MatrixXd::Constant(1, 1, 100.0);
  p.D = Eigen::MatrixXd::Zero(1, 1);
  p.dt = 1e-3;
  p.u_min = Eigen::VectorXd::Constant(1, -1.0);
  p.u_max = Eigen::VectorXd::Constant(1, 1.0);
  Eigen::VectorXd y = Eigen::VectorXd::Ones(1);
  p.anti_windup = AntiWindup::kHold;
  auto hold = StateSpaceController<double>::from_parameters(p);
  p.anti_windup = AntiWindup::kNone;
  auto none = StateSpaceController<double>::from_parameters(p);
  // 100 x reaches the limit 1 at x = 0.01, after 10 samples.
  for (int k = 0; k < 100; ++k) {
    hold.step(y);
    none.step(y);
  }
  // Held from the first clamped sample: x = 0.010 or 0.011 (the sum of ten 1e-3 rounds either
  // side of 0.01).
  CHECK(hold.state()(0) >= 0.01 - 1e-15);
  CHECK(hold.state()(0) <= 0.011 + 1e-15);
  CHECK(none.state()(0) == Approx(0.1).epsilon(1e-12));  // wound up: ten times the limit
  CHECK(hold.step(y)(0) == 1.0);
  // On release the held controller leaves the limit at once; the wound-up one stays for ~90
  // samples of the reversed input.
  y(0) = -1;
  int hold_release = -1, none_release = -1;
  for (int k = 0; k < 200; ++k) {
    if (hold.step(y)(0) < 1.0 && hold_release < 0) hold_release = k;
    if (none.step(y)(0) < 1.0 && none_release < 0) none_release = k;
  }
  CHECK(hold_release <= 2);
  CHECK(none_release >= 85);
}

TEST_CASE("the state-space controller starts bumplessly and follows its force through a delay",
          "[controller][state_space]") {
  const Loop l = random_loop(1, 3, 1, 3, 21);
  StateSpaceParameters p = parameters(l);
  p.feedthrough_delay = 2;
  auto c = StateSpaceController<double>::from_parameters(p);
  // C is 3 x 4 (full row rank): the start is exact.
  Eigen::VectorXd y(3), u(3);
  y << 0.3, -1.2, 0.7;
  u << 0.05, -0.02, 0.01;
  c.start(y, u);
  const Eigen::VectorXd first = c.step(y);
  CHECK((first - u).cwiseAbs().maxCoeff() <= 1e-12);
  // The delayed feedthrough: readings holding the command of 1 + d samples before, removed by a
  // controller told d = 2, give the commands that readings holding the previous command give a
  // controller told d = 0 (both see the same f).
  StateSpaceParameters q = p;
  q.feedthrough_delay = 0;
  auto delayed = StateSpaceController<double>::from_parameters(p);
  auto prompt = StateSpaceController<double>::from_parameters(q);
  const Eigen::MatrixXd D22 = p.feedthrough;
  std::vector<Eigen::VectorXd> sent;  // the delayed controller's commands, oldest first
  Eigen::VectorXd last = Eigen::VectorXd::Zero(3);
  std::mt19937 rng(4);
  std::normal_distribution<double> n01;
  double worst = 0, largest = 0;
  for (int k = 0; k < 500; ++k) {
    Eigen::VectorXd e(3);
    for (auto& v : e) v = n01(rng);
    const Eigen::VectorXd held3 =
        k >= 3 ? sent[static_cast<std::size_t>(k - 3)] : Eigen::VectorXd::Zero(3);
    const Eigen::VectorXd a = delayed.step(e + D22 * held3);
    const Eigen::VectorXd b = prompt.step(e + D22 * last);
    sent.push_back(a);
    last = b;
    worst = std::max(worst, (a - b).cwiseAbs().maxCoeff());
    largest = std::max(largest, a.cwiseAbs().maxCoeff());
  }
  CAPTURE(worst, largest);
  REQUIRE(largest > 0);
  CHECK(worst <= 1e-12 * largest);
}

TEST_CASE("a static gain (no states) commands u = D y and starts bumplessly where it can",
          "[controller][state_space]") {
  StateSpaceParameters p;
  p.A = Eigen::MatrixXd::Zero(0, 0);
  p.B = Eigen::MatrixXd::Zero(0, 2);
  p.C = Eigen::MatrixXd::Zero(3, 0);
  p.D = Eigen::MatrixXd::Random(3, 2);
  p.dt = 1e-3;
  auto c = StateSpaceController<double>::from_parameters(p);  // once a crash in Eigen (COD of 3x0)
  using V = StateSpaceController<double>::Vector;
  const V y = Eigen::VectorXd::Random(2);
  const Eigen::VectorXd u = c.step(y);
  CHECK((u - p.D * Eigen::VectorXd(y)).cwiseAbs().maxCoeff() <= 1e-15);
  c.start(y, V(Eigen::VectorXd::Ones(3)));  // no state to give another command: the law's own
  CHECK((Eigen::VectorXd(c.step(y)) - p.D * Eigen::VectorXd(y)).cwiseAbs().maxCoeff() <= 1e-15);
}

TEST_CASE("the state-space controller refuses what it cannot run, naming it",
          "[controller][state_space]") {
  const Loop l = random_loop(1, 2, 1, 2, 5);
  StateSpaceParameters p = parameters(l);
  SECTION("sizes") {
    p.B = Eigen::MatrixXd::Zero(p.A.rows(), 3);
    CHECK_THROWS_WITH(StateSpaceController<double>::from_parameters(p), Contains("D is 2x2"));
  }
  SECTION("a non-finite entry") {
    p.A(0, 0) = std::nan("");
    CHECK_THROWS_WITH(StateSpaceController<double>::from_parameters(p), Contains("not finite"));
  }
  SECTION("an ill-posed loop") {
    p.D = Eigen::MatrixXd::Identity(2, 2);
    p.feedthrough = Eigen::MatrixXd::Identity(2, 2);
    CHECK_THROWS_WITH(StateSpaceController<double>::from_parameters(p),
                      Contains("I - D D22 is singular"));
  }
  SECTION("limits") {
    p.u_min = Eigen::VectorXd::Constant(1, 1.0);
    p.u_max = Eigen::VectorXd::Constant(1, -1.0);
    CHECK_THROWS_WITH(StateSpaceController<double>::from_parameters(p), Contains("u_min"));
  }
  SECTION("a delay out of range") {
    p.feedthrough_delay = 99;
    CHECK_THROWS_WITH(StateSpaceController<double>::from_parameters(p),
                      Contains("feedthrough_delay"));
  }
}

TEST_CASE("the sampled loop of any controller has the poles of close_loop_sampled's loop",
          "[controller][state_space]") {
  // The design side's loop matrix (controller/design/sampled_loop_stability.hpp) with no hardware
  // between controller and plant: the poles of close_loop_sampled's loop, and nc more at z = 0
  // (the held force and the remembered command are one signal there).
  const Eigen::Index nc = 3, ns = 4;
  const Loop l = random_loop(0, nc, 0, ns, 13);
  controller::design::SampledLoopHardware hw;
  hw.removed_feedthrough = l.plant.sys.D;
  const Eigen::MatrixXd A = controller::design::sampled_loop_matrix(l.plant, l.controller, hw);
  const auto closed = plant::lti::close_loop_sampled(l.plant, l.controller, {0, 0});
  REQUIRE(A.rows() == closed.sys.nx() + nc);
  Eigen::VectorXcd ours = Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues();
  const Eigen::VectorXcd reference =
      Eigen::EigenSolver<Eigen::MatrixXd>(closed.sys.A, false).eigenvalues();
  std::vector<bool> used(static_cast<std::size_t>(ours.size()), false);
  // Poles near z = 0 share a cluster with the extra zero poles, where eigenvalues are found only to
  // about the square root of the rounding: they are compared more loosely.
  double worst = 0, worst_near_zero = 0;
  for (const auto& z : reference) {
    Eigen::Index best = -1;
    for (Eigen::Index i = 0; i < ours.size(); ++i)
      if (!used[static_cast<std::size_t>(i)] &&
          (best < 0 || std::abs(ours(i) - z) < std::abs(ours(best) - z)))
        best = i;
    used[static_cast<std::size_t>(best)] = true;
    (std::abs(z) > 1e-2 ? worst : worst_near_zero) =
        std::max(std::abs(z) > 1e-2 ? worst : worst_near_zero, std::abs(ours(best) - z));
  }
  CAPTURE(worst, worst_near_zero);
  CHECK(worst <= 1e-10);
  CHECK(worst_near_zero <= 1e-6);
  for (Eigen::Index i = 0; i < ours.size(); ++i)
    if (!used[static_cast<std::size_t>(i)]) CHECK(std::abs(ours(i)) <= 1e-7);
}
