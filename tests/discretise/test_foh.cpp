// SPDX-License-Identifier: BSD-3-Clause
// First-order (triangle) hold: with the input piecewise linear through the samples, the outputs
// of the shifted-state discrete system equal the exact continuous response at the samples.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"

using namespace flexloop::plant::lti;
using namespace flexloop::test;

namespace {
constexpr double kTol = 1e-10;
}

TEST_CASE("foh: double integrator under a ramp force matches r t^3/6m, r t^2/2m") {
  const double m = 1.7, dt = 2e-3, r = 4.0;
  const int steps = 1500;
  Eigen::MatrixXd A(2, 2), B(2, 1), C = Eigen::MatrixXd::Identity(2, 2),
                                    D = Eigen::MatrixXd::Zero(2, 1);
  A << 0, 1, 0, 0;
  B << 0, 1 / m;
  const auto c = labelled(A, B, C, D);
  const auto d = discretise(c, {.method = DiscretisationMethod::kFirstOrderHold, .dt = dt});

  std::vector<Eigen::VectorXd> u, ref;
  for (int k = 0; k < steps; ++k) {
    const double t = k * dt;
    u.push_back(Eigen::VectorXd::Constant(1, r * t));
    Eigen::VectorXd y(2);
    y << r * t * t * t / (6 * m), r * t * t / (2 * m);
    ref.push_back(y);
  }
  // x_0 = 0 and u_0 = 0, so the shifted state starts at 0 too.
  const auto y = simulate(d.sys, Eigen::VectorXd::Zero(2), u);
  const double err = relative_error(y, ref);
  INFO("foh ramp error " << err);
  CHECK(err <= kTol);

  // The same ramp through a zero-order hold is visibly wrong: the test discriminates.
  const auto z = discretise(c, {.method = DiscretisationMethod::kZeroOrderHold, .dt = dt});
  CHECK(relative_error(simulate(z.sys, Eigen::VectorXd::Zero(2), u), ref) > 1e-4);
}

TEST_CASE("foh: 12-state system under a random piecewise-linear input matches the modal solution") {
  const auto sys = make_modal_system(777);
  const double dt = 1e-3;
  const int steps = 3000;
  const auto d = discretise(sys.ss, {.method = DiscretisationMethod::kFirstOrderHold, .dt = dt});
  const Eigen::Index nu = sys.ss.nu();

  std::mt19937 rng(42);
  std::vector<Eigen::VectorXd> u{Eigen::VectorXd::Zero(nu)};
  for (int k = 1; k <= steps; ++k) u.push_back(random_matrix(rng, nu, 1));

  std::vector<Eigen::VectorXd> ref;
  auto state = sys.modal_from_z(Eigen::VectorXd::Zero(sys.ss.nx()));
  for (int k = 0; k < steps; ++k) {
    ref.push_back(sys.output(state, u[k]));
    state = sys.step(state, u[k], u[k + 1], dt);
  }
  u.pop_back();
  const auto y = simulate(d.sys, Eigen::VectorXd::Zero(sys.ss.nx()), u);
  const double err = relative_error(y, ref);
  INFO("foh piecewise-linear error " << err);
  CHECK(err <= kTol);
  // Ad is e^{AT}, as for zoh: same poles.
  double rho = 0;
  for (const auto& s : sys.eigenvalues()) rho = std::max(rho, std::abs(std::exp(s * dt)));
  CHECK(d.spectral_radius == Approx(rho).epsilon(1e-12));
}
