// SPDX-License-Identifier: BSD-3-Clause
// Frequency response and singular values against independent references: the analytic transfer
// function of a spring-mass-damper, a dense complex LU solve of (jwI - A) X = B, the closed-form
// singular values of a 2x2 matrix and Eigen's JacobiSVD.
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"
#include "tests/discretise/reference.hpp"  // labelled

using flexloop::plant::lti::balancing_scaling;
using flexloop::plant::lti::frequency_response;
using flexloop::plant::lti::FrequencyResponseOptions;
using flexloop::plant::lti::log_frequency_grid_hz;
using flexloop::plant::lti::singular_values;
using flexloop::plant::lti::StateSpace;
using flexloop::test::labelled;
using cd = std::complex<double>;

namespace {
using flexloop::numeric::kTwoPi;

Eigen::MatrixXd gaussian(Eigen::Index r, Eigen::Index c, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd m(r, c);
  for (Eigen::Index j = 0; j < c; ++j)
    for (Eigen::Index i = 0; i < r; ++i) m(i, j) = n(rng);
  return m;
}

// Random stable MIMO system: eigenvalues of A shifted into the left half plane.
StateSpace random_system(int n, int m, int p, std::mt19937& rng) {
  Eigen::MatrixXd A = gaussian(n, n, rng);
  const double shift = A.eigenvalues().real().maxCoeff() + 0.1;
  A -= shift * Eigen::MatrixXd::Identity(n, n);
  return labelled(A, gaussian(n, m, rng), gaussian(p, n, rng), gaussian(p, m, rng));
}

// Reference: dense complex LU solve of (jwI - A) X = B, no structure used.
Eigen::MatrixXcd direct(const StateSpace& s, double f) {
  const Eigen::Index n = s.nx();
  const Eigen::MatrixXcd M =
      cd(0.0, kTwoPi * f) * Eigen::MatrixXcd::Identity(n, n) - s.A.cast<cd>();
  return s.C.cast<cd>() * M.partialPivLu().solve(s.B.cast<cd>()) + s.D.cast<cd>();
}

double rel_err(const Eigen::MatrixXcd& a, const Eigen::MatrixXcd& ref) {
  return (a - ref).norm() / ref.norm();
}
}  // namespace

TEST_CASE("log frequency grid: inclusive end points, constant ratio, bad input refused",
          "[analysis][frequency]") {
  const auto f = log_frequency_grid_hz(0.01, 1000.0, 51);
  REQUIRE(f.size() == 51);
  CHECK(f.front() == 0.01);
  CHECK(f.back() == 1000.0);
  // 5 decades in 50 steps: each step multiplies by 10^(1/10).
  for (std::size_t i = 1; i < f.size(); ++i)
    CHECK(f[i] / f[i - 1] == Approx(std::pow(10.0, 0.1)).epsilon(1e-12));
  CHECK(f[10] == Approx(0.1).epsilon(1e-13));
  CHECK_THROWS_AS(log_frequency_grid_hz(0.0, 10.0, 10), std::invalid_argument);
  CHECK_THROWS_AS(log_frequency_grid_hz(10.0, 1.0, 10), std::invalid_argument);
  CHECK_THROWS_AS(log_frequency_grid_hz(1.0, 10.0, 1), std::invalid_argument);
}

TEST_CASE("spring-mass-damper response equals 1/(m s^2 + d s + k)", "[analysis][frequency]") {
  const double m = 2.5, d = 0.8, k = 4.0e4;  // f_n = 20.1 Hz, damping ratio 1.3e-3
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << 0, 1, -k / m, -d / m;
  B << 0, 1 / m;
  C << 1, 0;
  D << 0;
  const auto sys = labelled(A, B, C, D);
  auto f = log_frequency_grid_hz(0.01, 1000.0, 400);
  f.push_back(std::sqrt(k / m) / kTwoPi);  // right on the undamped natural frequency
  for (bool balance : {true, false}) {
    const auto G = frequency_response(sys, f, FrequencyResponseOptions{balance});
    REQUIRE(G.size() == f.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const cd s(0.0, kTwoPi * f[i]);
      const cd ref = 1.0 / (m * s * s + d * s + k);
      REQUIRE(G[i].rows() == 1);
      REQUIRE(G[i].cols() == 1);
      worst = std::max(worst, std::abs(G[i](0, 0) - ref) / std::abs(ref));
    }
    INFO("balance = " << balance << ", worst relative error " << worst);
    CHECK(worst <= 1e-12);
  }
}

TEST_CASE("cart with rheonomic inputs (DESIGN validation case 1): x2/x1 = G1(s)",
          "[analysis][frequency]") {
  // q = x2 - x1, u = (x1'', x1', x1); y = x2 = q + x1. Position input: combine columns with
  // s^2, s, 1 and compare with G1(s) = (d/m s + k/m) / (s^2 + d/m s + k/m).
  const double m = 1.3, d = 7.0, k = 2.0e3;
  Eigen::MatrixXd A(2, 2), B(2, 3), C(1, 2), D(1, 3);
  A << 0, 1, -k / m, -d / m;
  B << 0, 0, 0, -1, 0, 0;
  C << 1, 0;
  D << 0, 0, 1;
  const auto f = log_frequency_grid_hz(0.01, 1000.0, 200);
  const auto G = frequency_response(labelled(A, B, C, D), f);
  double worst = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const cd s(0.0, kTwoPi * f[i]);
    const cd g1 = G[i](0, 0) * s * s + G[i](0, 1) * s + G[i](0, 2);
    const cd ref = (d / m * s + k / m) / (s * s + d / m * s + k / m);
    worst = std::max(worst, std::abs(g1 - ref) / std::abs(ref));
  }
  INFO("worst relative error " << worst);
  // Tolerance: the column combination cancels; at 1 kHz |s^2 G(0,0)| / |G1| ~ 1e3, so rounding in
  // G(0,0) is amplified about a thousandfold (observed 7e-13).
  CHECK(worst <= 1e-11);
}

TEST_CASE("random 20-state MIMO response equals the dense complex solve", "[analysis][frequency]") {
  std::mt19937 rng(20240611);
  const auto f = log_frequency_grid_hz(0.01, 1000.0, 60);
  for (int trial = 0; trial < 5; ++trial) {
    const auto sys = random_system(20, 3, 4, rng);
    for (bool balance : {true, false}) {
      const auto G = frequency_response(sys, f, FrequencyResponseOptions{balance});
      double worst = 0.0;
      for (std::size_t i = 0; i < f.size(); ++i) {
        REQUIRE(G[i].rows() == 4);
        REQUIRE(G[i].cols() == 3);
        worst = std::max(worst, rel_err(G[i], direct(sys, f[i])));
      }
      INFO("trial " << trial << ", balance " << balance << ": worst relative error " << worst);
      CHECK(worst <= 1e-10);
    }
  }
}

TEST_CASE("badly scaled states: balancing is an exact power-of-two similarity",
          "[analysis][frequency]") {
  // Same system in states scaled by 10^-6 .. 10^6 (mixed units). G is invariant under the
  // similarity, so the well-scaled system's dense solve is the reference.
  std::mt19937 rng(7);
  const auto sys = random_system(20, 2, 3, rng);
  Eigen::VectorXd t(20);
  for (int i = 0; i < 20; ++i) t(i) = std::pow(10.0, -6.0 + 12.0 * i / 19.0);
  const auto scaled =
      labelled(t.cwiseInverse().asDiagonal() * sys.A * t.asDiagonal(),
               t.cwiseInverse().asDiagonal() * sys.B, sys.C * t.asDiagonal(), sys.D);
  const Eigen::VectorXd b = balancing_scaling(scaled.A);
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    int e = 0;
    CHECK(std::frexp(b(i), &e) == 0.5);  // a power of two
  }
  const Eigen::MatrixXd Ab = b.cwiseInverse().asDiagonal() * scaled.A * b.asDiagonal();
  CHECK(Ab.norm() < 1e-6 * scaled.A.norm());
  CHECK(Ab.diagonal() == scaled.A.diagonal());  // exact: diagonal untouched by the similarity

  const auto f = log_frequency_grid_hz(0.01, 1000.0, 40);
  const auto G = frequency_response(scaled, f);
  double worst = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i)
    worst = std::max(worst, rel_err(G[i], direct(sys, f[i])));
  INFO("worst relative error with balancing " << worst);
  CHECK(worst <= 1e-10);
}

TEST_CASE("frequency response edge cases", "[analysis][frequency]") {
  SECTION("a frequency on a pole is refused, naming it") {
    Eigen::MatrixXd A(1, 1), B(1, 1), C(1, 1), D(1, 1);
    A << 0;  // integrator: pole at s = 0
    B << 1;
    C << 1;
    D << 0;
    CHECK_THROWS_WITH(frequency_response(labelled(A, B, C, D), {1.0, 0.0}),
                      Catch::Contains("eigenvalue of A") && Catch::Contains("0 Hz"));
    const auto G = frequency_response(labelled(A, B, C, D), {1.0});
    CHECK(std::abs(G[0](0, 0) - 1.0 / cd(0.0, kTwoPi)) <= 1e-15);
  }
  SECTION("no states: the static gain D") {
    Eigen::MatrixXd D(2, 1);
    D << 3, -4;
    const auto G = frequency_response(
        labelled(Eigen::MatrixXd(0, 0), Eigen::MatrixXd(0, 1), Eigen::MatrixXd(2, 0), D),
        {0.5, 5.0});
    REQUIRE(G.size() == 2);
    CHECK(G[1].real() == D);
    CHECK(G[1].imag().isZero(0.0));
  }
  SECTION("an invalid system is refused") {
    auto sys = labelled(Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 1),
                        Eigen::MatrixXd::Zero(1, 2), Eigen::MatrixXd::Zero(1, 1));
    sys.inputs.clear();
    CHECK_THROWS_AS(frequency_response(sys, {1.0}), std::invalid_argument);
  }
}

TEST_CASE("singular values equal closed-form 2x2 values and JacobiSVD", "[analysis][frequency]") {
  std::mt19937 rng(99);
  const auto f = log_frequency_grid_hz(0.1, 100.0, 30);

  SECTION("two-channel system: closed form and JacobiSVD") {
    const auto sys = random_system(20, 2, 2, rng);
    const auto G = frequency_response(sys, f);
    const Eigen::MatrixXd sigma = singular_values(G);
    REQUIRE(sigma.rows() == static_cast<Eigen::Index>(f.size()));
    REQUIRE(sigma.cols() == 2);
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      // sigma1^2 + sigma2^2 = ||G||_F^2 and sigma1 sigma2 = |det G|.
      const double fro2 = G[i].squaredNorm();
      const double det = std::abs(G[i].determinant());
      const double s1 = std::sqrt(0.5 * (fro2 + std::sqrt(fro2 * fro2 - 4.0 * det * det)));
      const double s2 = det / s1;
      CHECK(sigma(k, 0) == Approx(s1).epsilon(1e-12));
      CHECK(sigma(k, 1) == Approx(s2).epsilon(1e-10));
      const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(G[i]);
      CHECK((sigma.row(k).transpose() - svd.singularValues()).norm() <=
            1e-12 * svd.singularValues()(0));
      CHECK(sigma(k, 0) >= sigma(k, 1));
    }
  }
  SECTION("wide MIMO (divide-and-conquer path in BDCSVD) against JacobiSVD") {
    const auto sys = random_system(20, 18, 20, rng);
    const auto G = frequency_response(sys, f);
    const Eigen::MatrixXd sigma = singular_values(G);
    REQUIRE(sigma.cols() == 18);
    for (std::size_t i = 0; i < f.size(); ++i) {
      const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(G[i]);
      const Eigen::VectorXd s = sigma.row(static_cast<Eigen::Index>(i)).transpose();
      CHECK((s - svd.singularValues()).norm() <= 1e-12 * svd.singularValues()(0));
      for (Eigen::Index j = 1; j < s.size(); ++j) CHECK(s(j - 1) >= s(j));
    }
  }
  SECTION("mismatched sizes are refused") {
    CHECK_THROWS_AS(singular_values({Eigen::MatrixXcd::Ones(2, 2), Eigen::MatrixXcd::Ones(2, 3)}),
                    std::invalid_argument);
  }
}

TEST_CASE(
    "unwrapped phase: a fourth-order lag reaches -360 without a jump, whole turns move the "
    "start within half a turn of zero",
    "[analysis][frequency]") {
  using flexloop::plant::lti::unwrapped_phase_deg;
  // G(s) = 1 / (s + 1)^4: phase -4 atan(w), from 0 to -360 degrees, through -180 at w = 1.
  const std::vector<double> f = log_frequency_grid_hz(1e-3, 1e2, 400);
  std::vector<cd> g, minus_g;
  for (const double fi : f) {
    const cd s(0.0, kTwoPi * fi);
    g.push_back(1.0 / std::pow(s + 1.0, 4));
    minus_g.push_back(-g.back());
  }
  const std::vector<double> ph = unwrapped_phase_deg(g), ph_minus = unwrapped_phase_deg(minus_g);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double exact = -4.0 * std::atan(kTwoPi * f[i]) * 180.0 / std::numbers::pi;
    CHECK(ph[i] == Approx(exact).margin(1e-9));
    // -G starts at +180 - 0.0x degrees, i.e. in (-180, 180], and follows G's curve 180 above it.
    CHECK(ph_minus[i] == Approx(exact + 180.0).margin(1e-9));
  }
  // A sequence that starts two turns down is shifted back; a NaN keeps its place.
  const std::vector<double> shifted = unwrapped_phase_deg(
      {std::polar(1.0, -4.0 * std::numbers::pi - 0.1), cd(NAN, 0.0), std::polar(1.0, -0.2)});
  CHECK(shifted[0] == Approx(-0.1 * 180.0 / std::numbers::pi));
  CHECK(std::isnan(shifted[1]));
  CHECK(shifted[2] == Approx(-0.2 * 180.0 / std::numbers::pi));
}

TEST_CASE(
    "with_resonances: a 0.2 % damped peak is drawn at its height, not cut between grid "
    "points",
    "[analysis][frequency]") {
  using flexloop::plant::lti::with_resonances;
  // G = wn^2 / (s^2 + 2 zeta wn s + wn^2): |G(j wn)| = 1 / (2 zeta) = 250 (48 dB).
  const double fn = 13.7, zeta = 0.002, wn = kTwoPi * fn;
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Zero(1, 1);
  A << 0.0, 1.0, -wn * wn, -2.0 * zeta * wn;
  B << 0.0, wn * wn;
  C << 1.0, 0.0;
  const StateSpace sys = labelled(A, B, C, D);
  const std::vector<double> grid = log_frequency_grid_hz(1.0, 100.0, 200);
  auto peak = [&](const std::vector<double>& f) {
    double m = 0.0;
    for (const Eigen::MatrixXcd& G : frequency_response(sys, f)) m = std::max(m, std::abs(G(0, 0)));
    return m;
  };
  const std::vector<double> refined = with_resonances(grid, Eigen::Vector2d(fn, 1e4));
  CHECK(refined.size() == grid.size() + 1);  // 1e4 Hz is outside the grid: not added
  CHECK(std::is_sorted(refined.begin(), refined.end()));
  CHECK(peak(refined) == Approx(1.0 / (2.0 * zeta)).epsilon(1e-9));
  // The plain grid (ratio 1.023 between points, the peak 0.4 % wide) misses it by more than 3 dB.
  CHECK(20.0 * std::log10(peak(grid) * 2.0 * zeta) < -3.0);
}
