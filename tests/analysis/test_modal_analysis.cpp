// SPDX-License-Identifier: BSD-3-Clause
// Natural modes, buckling multipliers and poles against analytic values: characteristic
// polynomials solved by hand, symmetry arguments for repeated eigenvalues, and the cofactor
// expansion of det(K + lambda G).
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <random>

#include "numeric/constants.hpp"
#include "plant/lti/modal_analysis.hpp"

using flexloop::plant::lti::buckling_multipliers;
using flexloop::plant::lti::Modes;
using flexloop::plant::lti::natural_modes;
using flexloop::plant::lti::poles;
using flexloop::plant::lti::StateSpace;
using cd = std::complex<double>;

namespace {
using flexloop::numeric::kTwoPi;
double hz(double omega2) {
  return std::sqrt(omega2) / kTwoPi;
}

Eigen::MatrixXd random_spd(int n, std::mt19937& rng, double floor) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd R(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) R(i, j) = g(rng);
  return R * R.transpose() + floor * Eigen::MatrixXd::Identity(n, n);
}

void check_mass_normalised(const Modes& modes, const Eigen::MatrixXd& M, const Eigen::MatrixXd& K) {
  const Eigen::Index n = M.rows();
  const Eigen::MatrixXd& P = modes.shapes;
  CHECK((P.transpose() * M * P - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff() <= 1e-12);
  Eigen::VectorXd w2(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double f = modes.frequencies_hz(i);
    w2(i) = (f < 0 ? -1.0 : 1.0) * (kTwoPi * f) * (kTwoPi * f);
  }
  const Eigen::MatrixXd PKP = P.transpose() * K * P;
  CHECK((PKP - Eigen::MatrixXd(w2.asDiagonal())).cwiseAbs().maxCoeff() <=
        1e-12 * K.cwiseAbs().maxCoeff() * M.inverse().cwiseAbs().maxCoeff() * n);
}
}  // namespace

TEST_CASE("2-DOF chain: analytic frequencies, mass-normalised shapes", "[analysis][modes]") {
  // wall -k1- m1 -k2- m2:  det(K - w^2 M) = m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0.
  const double m1 = 3.0, m2 = 1.5, k1 = 2.0e5, k2 = 5.0e4;
  Eigen::MatrixXd M(2, 2), K(2, 2);
  M << m1, 0, 0, m2;
  K << k1 + k2, -k2, -k2, k2;
  const double b = m1 * k2 + m2 * (k1 + k2), a = m1 * m2, c = k1 * k2;
  const double disc = std::sqrt(b * b - 4 * a * c);
  const double w2_hi = (b + disc) / (2 * a), w2_lo = c / (a * w2_hi);  // Vieta: no cancellation

  const Modes modes = natural_modes(M, K);
  REQUIRE(modes.frequencies_hz.size() == 2);
  CHECK(modes.frequencies_hz(0) == Approx(hz(w2_lo)).epsilon(1e-13));
  CHECK(modes.frequencies_hz(1) == Approx(hz(w2_hi)).epsilon(1e-13));
  check_mass_normalised(modes, M, K);
  // First mode in phase, second in antiphase; each shape solves (K - w^2 M) phi = 0.
  CHECK(modes.shapes(0, 0) * modes.shapes(1, 0) > 0);
  CHECK(modes.shapes(0, 1) * modes.shapes(1, 1) < 0);
  for (int i = 0; i < 2; ++i) {
    const double w2 = modes.omega_squared(i).real();
    CHECK(((K - w2 * M) * modes.shapes.col(i)).norm() <= 1e-9 * K.norm());
  }
}

TEST_CASE("3 masses on a ring: rigid-body mode and a repeated pair", "[analysis][modes]") {
  // Cyclic symmetry: w^2 = 0 (all move together) and w^2 = 3k/m twice.
  const double m = 0.7, k = 1.2e4;
  Eigen::MatrixXd M = m * Eigen::MatrixXd::Identity(3, 3), K(3, 3);
  K << 2, -1, -1, -1, 2, -1, -1, -1, 2;
  K *= k;
  const Modes modes = natural_modes(M, K);
  CHECK(modes.frequencies_hz(0) == 0.0);  // rounding-level w^2 is reported as exactly 0
  CHECK(modes.frequencies_hz(1) == Approx(hz(3 * k / m)).epsilon(1e-13));
  CHECK(modes.frequencies_hz(2) == Approx(hz(3 * k / m)).epsilon(1e-13));
  check_mass_normalised(modes, M, K);
  // The rigid-body shape is (1,1,1)/sqrt(3m).
  CHECK((modes.shapes.col(0) - Eigen::Vector3d::Constant(1.0 / std::sqrt(3 * m))).norm() <= 1e-12);
}

TEST_CASE("random SPD pair: Phi^T M Phi = I and Phi^T K Phi = diag(w^2)", "[analysis][modes]") {
  std::mt19937 rng(3);
  const Eigen::MatrixXd M = random_spd(8, rng, 1.0), K = random_spd(8, rng, 0.5) * 1e3;
  const Modes modes = natural_modes(M, K);
  check_mass_normalised(modes, M, K);
  for (Eigen::Index i = 1; i < 8; ++i)
    CHECK(modes.frequencies_hz(i - 1) <= modes.frequencies_hz(i));
  // Reference: eigenvalues of the dense M^-1 K (general solver on a different matrix).
  Eigen::VectorXd ref = (M.inverse() * K).eigenvalues().real();
  std::sort(ref.data(), ref.data() + ref.size());
  for (Eigen::Index i = 0; i < 8; ++i)
    CHECK(modes.frequencies_hz(i) == Approx(hz(ref(i))).epsilon(1e-10));
}

TEST_CASE("unstable and non-symmetric stiffness: sign convention", "[analysis][modes]") {
  SECTION("negative stiffness: divergence reported as a negative frequency") {
    Eigen::MatrixXd M(2, 2), K(2, 2);
    M << 2, 0, 0, 1;
    K << -8, 0, 0, 100;  // w^2 = -4 and 100
    const Modes modes = natural_modes(M, K);
    CHECK(modes.frequencies_hz(0) == Approx(-hz(4.0)).epsilon(1e-14));
    CHECK(modes.frequencies_hz(1) == Approx(hz(100.0)).epsilon(1e-14));
    CHECK(modes.omega_squared(0).real() == Approx(-4.0).epsilon(1e-14));
  }
  SECTION("non-symmetric K with a real spectrum (QZ path)") {
    // Upper triangular M^-1 K: eigenvalues are its diagonal, k1/m1 and k2/m2.
    Eigen::MatrixXd M(2, 2), K(2, 2);
    M << 2, 0, 0, 4;
    K << 50, 30, 0, 400;
    const Modes modes = natural_modes(M, K);
    CHECK(modes.frequencies_hz(0) == Approx(hz(25.0)).epsilon(1e-13));
    CHECK(modes.frequencies_hz(1) == Approx(hz(100.0)).epsilon(1e-13));
    for (int i = 0; i < 2; ++i) {
      const Eigen::VectorXd phi = modes.shapes.col(i);
      CHECK(phi.dot(M * phi) == Approx(1.0).epsilon(1e-13));
      CHECK(((K - modes.omega_squared(i).real() * M) * phi).norm() <= 1e-12 * K.norm());
    }
  }
  SECTION("circulatory K: flutter pair w^2 = k +- j c, both flagged negative") {
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2, 2), K(2, 2);
    const double k = 400, c = 300;
    K << k, c, -c, k;
    const Modes modes = natural_modes(M, K);
    const double mag = std::sqrt(std::abs(cd(k, c))) / kTwoPi;
    CHECK(modes.frequencies_hz(0) == Approx(-mag).epsilon(1e-13));
    CHECK(modes.frequencies_hz(1) == Approx(-mag).epsilon(1e-13));
    CHECK(std::abs(std::abs(modes.omega_squared(0).imag()) - c) <= 1e-10 * c);
  }
}

TEST_CASE("bad mass matrices are refused with the reason", "[analysis][modes]") {
  const Eigen::MatrixXd K = Eigen::MatrixXd::Identity(2, 2);
  Eigen::MatrixXd M(2, 2);
  M << 1, 0, 0, 0;  // a massless coordinate
  CHECK_THROWS_WITH(natural_modes(M, K),
                    Catch::Contains("singular") && Catch::Contains("massless"));
  M << 1, 0, 0, -1;
  CHECK_THROWS_WITH(natural_modes(M, K), Catch::Contains("indefinite"));
  M << 1, 0.5, 0, 1;
  CHECK_THROWS_WITH(natural_modes(M, K), Catch::Contains("not symmetric"));
  CHECK_THROWS_AS(natural_modes(Eigen::MatrixXd::Identity(3, 3), K), std::invalid_argument);
  // A massless combination, though every coordinate has mass: M = v v^T with v = [1, 1].
  M << 1, 1, 1, 1;
  CHECK_THROWS_WITH(natural_modes(M, K),
                    Catch::Contains("singular") && Catch::Contains("massless"));
}

TEST_CASE("a definite mass matrix of condition 1e11 is taken, not called singular",
          "[analysis][modes]") {
  // Issue 57: a lumped beam chain's M has translational masses of 1e1..1e7 and rotary inertias of
  // 1e-4: condition 1e11, positive definite. Reference: two uncoupled oscillators whose mass
  // spread is 1e11, k/m given exactly: w^2 = k_i / m_i, here 4 and 9 (rad/s)^2, and the same
  // pair rotated by an orthogonal Q (M = Q D Q^T, K = Q diag(k) Q^T), so that M is full.
  Eigen::MatrixXd M = Eigen::Vector2d(1e7, 1e-4).asDiagonal(),
                  K = Eigen::Vector2d(4e7, 9e-4).asDiagonal();
  auto modes = natural_modes(M, K);
  CHECK(modes.omega_squared(0).real() == Approx(4).epsilon(1e-12));
  CHECK(modes.omega_squared(1).real() == Approx(9).epsilon(1e-12));
  // Coupled: the massive coordinate drives the light one through the mass matrix.
  M << 1e7, 1e-2, 1e-2, 1e-4;  // determinant 1e3 - 1e-4 > 0: definite, condition ~1e11
  K = Eigen::Vector2d(4e7, 9e-4).asDiagonal();
  modes = natural_modes(M, K);
  // Reference: det(K - w^2 M) = 0, a quadratic in w^2 solved here in closed form.
  const double a = M.determinant(), b = -(K(0, 0) * M(1, 1) + K(1, 1) * M(0, 0)),
               c = K(0, 0) * K(1, 1);
  const double disc = std::sqrt(b * b - 4 * a * c), w2_low = 2 * c / (-b + disc),
               w2_high = (-b + disc) / (2 * a);
  CHECK(modes.omega_squared(0).real() == Approx(w2_low).epsilon(1e-9));
  CHECK(modes.omega_squared(1).real() == Approx(w2_high).epsilon(1e-9));
}

TEST_CASE("buckling multipliers", "[analysis][buckling]") {
  SECTION("K = k I, G = -g I: lambda = k/g, n times") {
    const double k = 5.0e3, g = 2.0;
    const Eigen::VectorXd lam = buckling_multipliers(k * Eigen::MatrixXd::Identity(4, 4),
                                                     -g * Eigen::MatrixXd::Identity(4, 4));
    REQUIRE(lam.size() == 4);
    for (Eigen::Index i = 0; i < 4; ++i) CHECK(lam(i) == Approx(k / g).epsilon(1e-14));
  }
  SECTION("2-DOF rigid-bar column: lambda = (k/L)(3 -+ sqrt 5)/2") {
    // Two rigid bars of length L, rotational springs k at the base and the joint, unit axial load
    // at the top. V = k/2 t1^2 + k/2 (t2 - t1)^2 - P L/2 (t1^2 + t2^2):
    // K = k [2 -1; -1 1], G = -L I for P = 1.
    const double k = 800.0, L = 0.4;
    Eigen::MatrixXd K(2, 2), G(2, 2);
    K << 2 * k, -k, -k, k;
    G = -L * Eigen::MatrixXd::Identity(2, 2);
    const Eigen::VectorXd lam = buckling_multipliers(K, G);
    REQUIRE(lam.size() == 2);
    CHECK(lam(0) == Approx(k / L * (3 - std::sqrt(5.0)) / 2).epsilon(1e-13));
    CHECK(lam(1) == Approx(k / L * (3 + std::sqrt(5.0)) / 2).epsilon(1e-13));
  }
  SECTION("singular G (unloaded coordinates): one finite multiplier from the cofactor expansion") {
    // G = diag(g, 0, 0): det(K + lambda G) = det K + lambda g det K[1:3,1:3] = 0.
    std::mt19937 rng(11);
    const Eigen::MatrixXd K = random_spd(3, rng, 1.0);
    const double g = -0.75;
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3, 3);
    G(0, 0) = g;
    const Eigen::VectorXd lam = buckling_multipliers(K, G);
    REQUIRE(lam.size() == 1);
    const double ref = -K.determinant() / (g * K.bottomRightCorner(2, 2).determinant());
    CHECK(lam(0) == Approx(ref).epsilon(1e-12));
    CHECK(buckling_multipliers(K, Eigen::MatrixXd::Zero(3, 3)).size() == 0);
  }
  SECTION("indefinite G: signed multipliers sorted by magnitude") {
    Eigen::MatrixXd K(2, 2), G(2, 2);
    K << 30, 0, 0, 20;
    G << 1, 0, 0, -1;  // lambda = -30 and +20
    const Eigen::VectorXd lam = buckling_multipliers(K, G);
    REQUIRE(lam.size() == 2);
    CHECK(lam(0) == Approx(20.0).epsilon(1e-14));
    CHECK(lam(1) == Approx(-30.0).epsilon(1e-14));
  }
  SECTION("non-symmetric K (QZ path) with a singular G") {
    // K upper triangular, G = diag(-1, -1, 0): det = (k11 - l)(k22 - l) k33 -> lambda = k11, k22.
    Eigen::MatrixXd K(3, 3), G = Eigen::MatrixXd::Zero(3, 3);
    K << 7, 2, 1, 0, 3, 4, 0, 0, 5;
    G(0, 0) = G(1, 1) = -1;
    const Eigen::VectorXd lam = buckling_multipliers(K, G);
    REQUIRE(lam.size() == 2);
    CHECK(lam(0) == Approx(3.0).epsilon(1e-12));
    CHECK(lam(1) == Approx(7.0).epsilon(1e-12));
  }
  SECTION("a singular pencil is refused") {
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(2, 2), G = Eigen::MatrixXd::Zero(2, 2);
    K(0, 0) = 1;
    K(0, 1) = 0.5;  // non-symmetric, so the QZ path sees the common null direction e2
    G(0, 0) = -1;
    CHECK_THROWS_WITH(buckling_multipliers(K, G), Catch::Contains("singular for every lambda"));
  }
}

TEST_CASE("poles: analytic eigenvalues in |imag|, real order", "[analysis][poles]") {
  const double m = 2.0, d = 3.0, k = 800.0;  // wd = sqrt(k/m - (d/2m)^2)
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6, 6);
  A.block(0, 0, 2, 2) << 0, 1, -k / m, -d / m;
  A(2, 2) = -5.0;
  A(3, 3) = 0.0;
  A.block(4, 4, 2, 2) << 0, 1, -4, 0;  // +-2j
  StateSpace sys{A,
                 Eigen::MatrixXd::Zero(6, 1),
                 Eigen::MatrixXd::Zero(1, 6),
                 Eigen::MatrixXd::Zero(1, 1),
                 {"a", "b", "c", "d", "e", "f"},
                 {"u"},
                 {"y"}};
  const double sigma = -d / (2 * m), wd = std::sqrt(k / m - sigma * sigma);
  const std::vector<cd> expected{{-5, 0}, {0, 0}, {0, -2}, {0, 2}, {sigma, -wd}, {sigma, wd}};
  const Eigen::VectorXcd p = poles(sys);
  REQUIRE(p.size() == 6);
  for (int i = 0; i < 6; ++i) {
    INFO("pole " << i << ": " << p(i) << " expected " << expected[static_cast<std::size_t>(i)]);
    CHECK(std::abs(p(i) - expected[static_cast<std::size_t>(i)]) <= 1e-12 * 20.0);
  }
}
