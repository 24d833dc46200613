// SPDX-License-Identifier: BSD-3-Clause
// Zero-order hold: step and impulse responses at the sample instants equal the exact continuous
// solution (analytic formulas, or the modal closed form) to 1e-10 of the response's size.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"

using namespace flexloop::plant::lti;
using namespace flexloop::test;

namespace {

constexpr double kTol = 1e-10;

std::vector<Eigen::VectorXd> constant_input(Eigen::VectorXd u, int steps) {
  return std::vector<Eigen::VectorXd>(static_cast<std::size_t>(steps), std::move(u));
}

DiscreteStateSpace zoh(const StateSpace& c, double dt) {
  return discretise(c, {.method = DiscretisationMethod::kZeroOrderHold, .dt = dt});
}

}  // namespace

TEST_CASE("zoh: underdamped 2nd order step and impulse match the analytic response") {
  // G(s) = wn^2 / (s^2 + 2 zeta wn s + wn^2) with x = (y, dy/dt).
  const double wn = 2 * std::numbers::pi * 10, zeta = 0.1, dt = 1e-3;
  const double wd = wn * std::sqrt(1 - zeta * zeta);
  const int steps = 1500;
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << 0, 1, -wn * wn, -2 * zeta * wn;
  B << 0, wn * wn;
  C << 1, 0;
  D << 0;
  const auto d = zoh(labelled(A, B, C, D), dt);

  std::vector<Eigen::VectorXd> step_ref, impulse_ref;
  for (int k = 0; k < steps; ++k) {
    const double t = k * dt;
    const double decay = std::exp(-zeta * wn * t);
    step_ref.push_back(Eigen::VectorXd::Constant(
        1, 1 - decay * (std::cos(wd * t) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * t))));
    impulse_ref.push_back(
        Eigen::VectorXd::Constant(1, wn / std::sqrt(1 - zeta * zeta) * decay * std::sin(wd * t)));
  }
  const auto step =
      simulate(d.sys, Eigen::VectorXd::Zero(2), constant_input(Eigen::VectorXd::Ones(1), steps));
  // A unit impulse puts the state at B at t = 0+; afterwards the response is the free one.
  const auto impulse = simulate(d.sys, B, constant_input(Eigen::VectorXd::Zero(1), steps));
  const double step_err = relative_error(step, step_ref);
  const double impulse_err = relative_error(impulse, impulse_ref);
  INFO("step " << step_err << ", impulse " << impulse_err);
  CHECK(step_err <= kTol);
  CHECK(impulse_err <= kTol);
  CHECK(d.spectral_radius == Approx(std::exp(-zeta * wn * dt)).epsilon(1e-12));
}

TEST_CASE("zoh: mass with integrators (singular A) matches t^3/6, t^2/2, t") {
  // States (integral of position, position, velocity) of a mass m under a force: a 3x3 Jordan
  // block at 0, so A is singular and has no inverse to lean on.
  const double m = 2.5, dt = 1e-3, force = 3.0;
  const int steps = 2000;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3), B(3, 1), C = Eigen::MatrixXd::Identity(3, 3),
                  D(3, 1);
  A(0, 1) = 1;
  A(1, 2) = 1;
  B << 0, 0, 1 / m;
  D << 0, 0, 0.5;  // a direct term, which zoh must pass through unchanged
  const auto d = zoh(labelled(A, B, C, D), dt);
  CHECK(d.spectral_radius == Approx(1.0).epsilon(1e-12));

  std::vector<Eigen::VectorXd> step_ref, impulse_ref;
  for (int k = 0; k < steps; ++k) {
    const double t = k * dt;
    Eigen::VectorXd s(3), i(3);
    s << force * t * t * t / (6 * m), force * t * t / (2 * m), force * t / m + 0.5 * force;
    i << t * t / (2 * m), t / m, 1 / m;
    step_ref.push_back(s);
    impulse_ref.push_back(i);
  }
  const auto step = simulate(d.sys, Eigen::VectorXd::Zero(3),
                             constant_input(Eigen::VectorXd::Constant(1, force), steps));
  const auto impulse = simulate(d.sys, B, constant_input(Eigen::VectorXd::Zero(1), steps));
  const double step_err = relative_error(step, step_ref);
  const double impulse_err = relative_error(impulse, impulse_ref);
  INFO("step " << step_err << ", impulse " << impulse_err);
  CHECK(step_err <= kTol);
  CHECK(impulse_err <= kTol);
}

TEST_CASE("zoh: 12-state random stable system matches the modal closed-form solution") {
  const auto sys = make_modal_system(20240605);
  const double dt = 1e-3;
  const int steps = 3000;
  const auto d = zoh(sys.ss, dt);
  const Eigen::Index nu = sys.ss.nu();

  for (Eigen::Index j = 0; j < nu; ++j) {
    DYNAMIC_SECTION("input " << j) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(nu, j), zero = Eigen::VectorXd::Zero(nu);
      std::vector<Eigen::VectorXd> step_ref, impulse_ref;
      auto step_state = sys.modal_from_z(Eigen::VectorXd::Zero(sys.ss.nx()));
      auto impulse_state = sys.modal_from_z(sys.Bz.col(j));
      for (int k = 0; k < steps; ++k) {
        step_ref.push_back(sys.output(step_state, e));
        impulse_ref.push_back(sys.output(impulse_state, zero));
        step_state = sys.step(step_state, e, e, dt);
        impulse_state = sys.step(impulse_state, zero, zero, dt);
      }
      const auto step =
          simulate(d.sys, Eigen::VectorXd::Zero(sys.ss.nx()), constant_input(e, steps));
      const auto impulse = simulate(d.sys, sys.ss.B.col(j), constant_input(zero, steps));
      const double step_err = relative_error(step, step_ref);
      const double impulse_err = relative_error(impulse, impulse_ref);
      INFO("step " << step_err << ", impulse " << impulse_err);
      CHECK(step_err <= kTol);
      CHECK(impulse_err <= kTol);
    }
  }
  // The discrete poles are e^{λT} of the known continuous ones.
  double rho = 0;
  for (const auto& s : sys.eigenvalues()) rho = std::max(rho, std::abs(std::exp(s * dt)));
  CHECK(d.spectral_radius == Approx(rho).epsilon(1e-12));
  CHECK(d.sys.states == sys.ss.states);
  CHECK(d.sys.inputs == sys.ss.inputs);
  CHECK(d.sys.outputs == sys.ss.outputs);
}
