// SPDX-License-Identifier: BSD-3-Clause
// Element translational mass: total mass and first moments for rigid translation, and the
// kinetic energy of a linear velocity field, which the consistent matrix must reproduce exactly
// (checked against Gauss quadrature of (m/2) int_0^1 |v(s)|^2 ds, not against the formula).
#include <catch2/catch.hpp>

#include <random>
#include <stdexcept>

#include "plant/model/element_properties.hpp"

using namespace flexloop::plant::model;

TEST_CASE("element mass: rigid translation carries the total mass", "[elements][mass]") {
  const double m = 2.75;
  for (int dim : {2, 3}) {
    for (bool consistent : {false, true}) {
      const Eigen::MatrixXd M = element_translational_mass(m, dim, consistent);
      INFO("dim " << dim << " consistent " << consistent);
      REQUIRE(M.rows() == 2 * dim);
      REQUIRE(M.cols() == 2 * dim);
      CHECK((M - M.transpose()).norm() == 0.0);
      CHECK(M.ldlt().isPositive());
      for (int a = 0; a < dim; ++a) {
        // Unit translation along axis a of both nodes: 1^T M 1 = m, and no coupling to the
        // other axes (first moment m along a only).
        Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * dim);
        u(a) = u(dim + a) = 1.0;
        CHECK(u.dot(M * u) == Approx(m).epsilon(1e-15));
        const Eigen::VectorXd f = M * u;  // inertia force of a unit acceleration along a
        CHECK(f(a) + f(dim + a) == Approx(m).epsilon(1e-15));
        for (int b = 0; b < dim; ++b)
          if (b != a) CHECK(f(b) + f(dim + b) == 0.0);
      }
      // Lumped mass is diagonal with m/2 per end.
      if (!consistent)
        CHECK((M - (m / 2) * Eigen::MatrixXd::Identity(2 * dim, 2 * dim)).norm() == 0.0);
    }
  }
}

TEST_CASE("consistent element mass gives the exact kinetic energy of linear interpolation",
          "[elements][mass]") {
  const double m = 1.9;
  std::mt19937 rng(41);
  std::normal_distribution<double> n(0.0, 1.0);
  // 2-point Gauss-Legendre on [0, 1] is exact for the quadratic |v(s)|^2.
  const double g = 0.5 / std::sqrt(3.0);
  const double s_pts[2] = {0.5 - g, 0.5 + g};
  for (int dim : {2, 3}) {
    const Eigen::MatrixXd M = element_translational_mass(m, dim, true);
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd v(2 * dim);
      for (int i = 0; i < 2 * dim; ++i) v(i) = n(rng);
      double T = 0.0;
      for (double s : s_pts) {
        const Eigen::VectorXd vs = (1 - s) * v.head(dim) + s * v.tail(dim);
        T += 0.5 * (m / 2) * vs.squaredNorm();  // weight 1/2 per point
      }
      CHECK(0.5 * v.dot(M * v) == Approx(T).epsilon(1e-14));
    }
  }
}

TEST_CASE("element mass rejects a bad dimension or a negative mass", "[elements][mass]") {
  CHECK_THROWS_AS(element_translational_mass(1.0, 1, false), std::invalid_argument);
  CHECK_THROWS_AS(element_translational_mass(1.0, 4, true), std::invalid_argument);
  CHECK_THROWS_AS(element_translational_mass(-1.0, 3, true), std::invalid_argument);
  CHECK(element_translational_mass(0.0, 3, true).norm() == 0.0);
}
