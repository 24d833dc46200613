// SPDX-License-Identifier: BSD-3-Clause
// The two Schur-form engines a campaign sample runs on, against independent references:
// - plant/lti/schur_transfer: C (pI - A)^-1 B against a dense complex LU solve of (pI - A) X = B,
//   on a random stable system, on one with a delay chain (a nilpotent Jordan block: no
//   eigenbasis) and one with a double integrator at z = 1, near the unit circle;
// - plant/lti/stable_covariance: P = A P A^T + B B^T against the doubling sum
//   (numeric/stationary_covariance.hpp) for a strictly stable random system, against the closed
//   form b^2 / (1 - a^2) of a first-order mode beside an integrator the noise drives (the
//   integrator split off, the drive reported), with a double integrator on the circle, and the
//   refusals (a mode outside the circle).
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <random>

#include "numeric/stationary_covariance.hpp"
#include "plant/lti/schur_transfer.hpp"
#include "plant/lti/stable_covariance.hpp"
#include "tests/discretise/reference.hpp"  // random_matrix

using Eigen::MatrixXcd;
using Eigen::MatrixXd;
using flexloop::plant::lti::SchurTransfer;
using flexloop::plant::lti::stable_covariance;
using cd = std::complex<double>;
using flexloop::test::random_matrix;

namespace {

// A random discrete system with spectral radius `radius` (scaled Gaussian A).
MatrixXd random_with_radius(Eigen::Index n, double radius, std::mt19937& rng) {
  const MatrixXd a = random_matrix(rng, n, n);
  const double rho = Eigen::EigenSolver<MatrixXd>(a, false).eigenvalues().cwiseAbs().maxCoeff();
  return a * (radius / rho);
}

MatrixXcd dense_solve(const MatrixXd& A, const MatrixXd& B, const MatrixXd& C, cd p) {
  MatrixXcd m = -A.cast<cd>();
  m.diagonal().array() += p;
  return C.cast<cd>() * m.fullPivLu().solve(B.cast<cd>());
}

double relative_difference(const MatrixXcd& a, const MatrixXcd& b) {
  return (a - b).norm() / b.norm();
}

// z - 1 for z on the unit circle at angle theta, without cancellation.
cd circle_minus_one(double theta) {
  const double h = std::sin(theta / 2);
  return {-2 * h * h, std::sin(theta)};
}

}  // namespace

TEST_CASE("Schur transfer: a random stable system equals a dense LU solve at points on the circle",
          "[schur]") {
  std::mt19937 rng(7);
  const MatrixXd A = random_with_radius(20, 0.98, rng), B = random_matrix(rng, 20, 3),
                 C = random_matrix(rng, 4, 20);
  const SchurTransfer h(A, B, C, 1.0);
  MatrixXcd g;
  for (const double theta : {1e-5, 1e-3, 0.1, 1.0, 3.0}) {
    REQUIRE(h.evaluate(circle_minus_one(theta), g));
    CHECK(relative_difference(g, dense_solve(A, B, C, std::polar(1.0, theta))) < 1e-11);
  }
}

TEST_CASE("Schur transfer: a delay chain (nilpotent Jordan block) and a double integrator at z = 1",
          "[schur]") {
  // x1 <- x2 <- x3 <- u (three delays, eigenvalue 0 three times, one Jordan block), a lightly
  // damped mode, and a double integrator [[1, 1], [0, 1]] driven by the last delay.
  MatrixXd A = MatrixXd::Zero(7, 7);
  A(0, 1) = A(1, 2) = 1;
  A.block(3, 3, 2, 2) << 0.9990, 0.0300, -0.0300, 0.9990;
  A(3, 0) = 1;
  A.block(5, 5, 2, 2) << 1, 1, 0, 1;
  A(6, 0) = 0.5;
  MatrixXd B = MatrixXd::Zero(7, 1), C = MatrixXd::Zero(2, 7);
  B(2, 0) = 1;
  C(0, 3) = 1;
  C(0, 0) = 0.25;
  C(1, 5) = 1;
  const SchurTransfer h(A, B, C, 1.0);
  const Eigen::VectorXcd poles = h.poles();
  CHECK(poles.cwiseAbs().minCoeff() < 1e-4);  // the chain's zeros (computed to eps^(1/3))
  MatrixXcd g;
  for (const double theta : {1e-2, 0.02, 0.03, 0.5, 2.5}) {
    REQUIRE(h.evaluate(circle_minus_one(theta), g));
    CHECK(relative_difference(g, dense_solve(A, B, C, std::polar(1.0, theta))) < 1e-9);
  }
}

TEST_CASE("Stable covariance: a strictly stable random system equals the doubling sum", "[schur]") {
  std::mt19937 rng(11);
  const MatrixXd A = random_with_radius(30, 0.995, rng), B = random_matrix(rng, 30, 4);
  const auto c = stable_covariance(A, B, 1e-9);
  const auto reference = flexloop::numeric::stationary_covariance(A, B);
  REQUIRE(reference);
  CHECK(c.on_circle == 0);
  CHECK(c.driven == 0);
  CHECK((c.P - *reference).norm() / reference->norm() < 1e-10);
  // And it solves the equation it claims to.
  CHECK((A * c.P * A.transpose() + B * B.transpose() - c.P).norm() / c.P.norm() < 1e-12);
}

TEST_CASE("Stable covariance: a first-order mode beside an integrator the noise drives",
          "[schur]") {
  // x1 = a x1 + b n1 + coupling x2; x2 = x2 + n2 (an integrator, the noise reaches it).
  const double a = 0.95, b = 0.3;
  MatrixXd A(2, 2), B(2, 2);
  A << a, 0.2, 0, 1;
  B << b, 0, 0, 1;
  const auto c = stable_covariance(A, B, 1e-9);
  CHECK(c.on_circle == 1);
  CHECK(c.driven > 0.1);
  // The part inside: y = x1 - X x2 with (a - 1) X = -0.2, y' = a y + (b n1 - X n2): its variance
  // is (b^2 + X^2) / (1 - a^2), in x's coordinates along e1 (the subspace of mode a).
  const double X = 0.2 / (1 - a);
  const double variance = (b * b + X * X) / (1 - a * a);
  CHECK(std::abs(c.P(0, 0) - variance) < 1e-12 * variance);
  CHECK(std::abs(c.P(1, 1)) < 1e-12 * variance);
  CHECK(std::abs(c.P(0, 1)) < 1e-12 * variance);
  // The noise kept off the integrator: nothing drives it, nothing reported.
  MatrixXd B_off(2, 1);
  B_off << b, 0;
  const auto off = stable_covariance(A, B_off, 1e-9);
  CHECK(off.driven < 1e-15);
  CHECK(std::abs(off.P(0, 0) - b * b / (1 - a * a)) < 1e-12 * b * b / (1 - a * a));
}

TEST_CASE(
    "Stable covariance: a double integrator on the circle beside a stable mode, and the refusals",
    "[schur]") {
  MatrixXd A(3, 3), B(3, 1);
  A << 0.5, 0.1, 0.0, 0, 1, 1, 0, 0, 1;
  B << 1, 0, 0;
  const auto c = stable_covariance(A, B, 1e-9);
  CHECK(c.on_circle == 2);
  CHECK(std::abs(c.P(0, 0) - 1 / (1 - 0.25)) < 1e-12);
  MatrixXd unstable = A;
  unstable(0, 0) = 1.01;
  CHECK_THROWS_WITH(stable_covariance(unstable, B, 1e-9), "the loop is unstable");
  CHECK_THROWS_AS(stable_covariance(A, MatrixXd::Zero(2, 1), 1e-9), std::invalid_argument);
}
