// SPDX-License-Identifier: BSD-3-Clause
// Model reduction (plant/lti/model_reduction.hpp) against references it did not produce:
//   - balanced truncation: the Hankel singular values against sqrt(eig(P Q)) with the Gramians
//     solved here by a Kronecker (vectorised) Lyapunov solve; the error of every reduced order
//     within the a-priori bound 2 Σ σ_discarded on a dense grid; the bound itself never below
//     the measured error's lower bound σ_{r+1};
//   - modal truncation: on a system of known modes hidden in a random basis, the kept poles are
//     the modes of largest contribution, the static correction makes the DC gain exact, and a
//     pole at the origin is always kept, a Jordan block there too (the floor's double
//     integrator); A defective elsewhere is refused.
// The systems are built here (not a shipped model).
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/model_reduction.hpp"

using namespace flexloop::plant::lti;
using Eigen::MatrixXd;

namespace {

using flexloop::numeric::kTwoPi;

struct ModeSpec {
  double f_hz, zeta;  // zeta >= 1: a real pole at -2 pi f; f = 0: a pole at the origin
};

// dx/dt = A x + B u, y = C x with the given modes in a random, well-conditioned basis.
StateSpace modal_system(const std::vector<ModeSpec>& modes, int nu, int ny, unsigned seed) {
  int n = 0;
  for (const auto& m : modes) n += m.zeta >= 1 || m.f_hz == 0 ? 1 : 2;
  MatrixXd L = MatrixXd::Zero(n, n);
  int i = 0;
  for (const auto& m : modes) {
    const double w = kTwoPi * m.f_hz;
    if (m.f_hz == 0) {
      i += 1;
    } else if (m.zeta >= 1) {
      L(i, i) = -w;
      i += 1;
    } else {
      const double a = -m.zeta * w, b = w * std::sqrt(1 - m.zeta * m.zeta);
      L.block<2, 2>(i, i) << a, b, -b, a;
      i += 2;
    }
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto random = [&](int r, int c) {
    MatrixXd m(r, c);
    for (int k = 0; k < r * c; ++k) m.data()[k] = u(rng);
    return m;
  };
  const MatrixXd S = MatrixXd::Identity(n, n) + 0.3 * random(n, n);
  StateSpace s;
  s.A = S * L * S.inverse();
  s.B = S * random(n, nu);
  s.C = random(ny, n) * S.inverse();
  s.D = MatrixXd::Zero(ny, nu);
  for (int k = 0; k < n; ++k) s.states.push_back("x" + std::to_string(k));
  for (int k = 0; k < nu; ++k) s.inputs.push_back("u" + std::to_string(k));
  for (int k = 0; k < ny; ++k) s.outputs.push_back("y" + std::to_string(k));
  return s;
}

// A X + X A^T + Q = 0 by the vectorised form (I ⊗ A + A ⊗ I) vec X = -vec Q.
MatrixXd lyapunov(const MatrixXd& A, const MatrixXd& Q) {
  const Eigen::Index n = A.rows();
  MatrixXd K = MatrixXd::Zero(n * n, n * n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      K.block(i * n, j * n, n, n) += (i == j ? 1.0 : 0.0) * A;
      K.block(i * n, j * n, n, n).diagonal().array() += A(i, j);
    }
  const Eigen::VectorXd x =
      K.fullPivLu().solve(-Eigen::Map<const Eigen::VectorXd>(Q.data(), n * n));
  return Eigen::Map<const MatrixXd>(x.data(), n, n);
}

// max over a dense grid of sigma_max(G1 - G2): a lower bound of the H-inf norm of the difference.
double hinf_difference(const StateSpace& a, const StateSpace& b, double f_lo, double f_hi) {
  const auto f = log_frequency_grid_hz(f_lo, f_hi, 4000);
  const auto ga = frequency_response(a, f), gb = frequency_response(b, f);
  double worst = 0;
  for (std::size_t k = 0; k < f.size(); ++k)
    worst = std::max(worst, Eigen::JacobiSVD<Eigen::MatrixXcd>(ga[k] - gb[k]).singularValues()(0));
  return worst;
}

}  // namespace

TEST_CASE(
    "balanced truncation: Hankel singular values as sqrt(eig(P Q)), every order within the "
    "a-priori bound") {
  const StateSpace s =
      modal_system({{2, 0.05}, {7, 0.02}, {15, 0.1}, {40, 0.03}, {90, 0.2}, {300, 1.5}}, 2, 3, 11);
  const Eigen::Index n = s.nx();
  REQUIRE(n == 11);
  const MatrixXd P = lyapunov(s.A, s.B * s.B.transpose());
  const MatrixXd Q = lyapunov(s.A.transpose(), s.C.transpose() * s.C);
  Eigen::VectorXd hsv = Eigen::EigenSolver<MatrixXd>(P * Q).eigenvalues().real().cwiseSqrt();
  std::sort(hsv.data(), hsv.data() + n, std::greater<>());

  for (int order = 1; order < n; ++order) {
    const ReducedModel r = balanced_truncation(s, order);
    INFO("order " << order);
    REQUIRE(r.sys.nx() == order);
    REQUIRE(r.hankel_singular_values.size() == n);
    for (Eigen::Index k = 0; k < n; ++k)
      CHECK(r.hankel_singular_values(k) == Approx(hsv(k)).epsilon(1e-6).margin(1e-12 * hsv(0)));
    CHECK(r.error_bound == Approx(2 * hsv.tail(n - order).sum()).epsilon(1e-6));
    const double error = hinf_difference(s, r.sys, 0.01, 1e4);
    CHECK(error <= r.error_bound * (1 + 1e-9));
    // The H-inf error of any order-r approximation is at least sigma_{r+1}; the grid's maximum
    // is a lower estimate of it, so it may fall short, but not by much on this dense grid.
    CHECK(error >= 0.5 * hsv(order));
    CHECK(r.sys.inputs == s.inputs);
    CHECK(r.sys.outputs == s.outputs);
  }
}

TEST_CASE("balanced truncation keeps a pole at the origin whole and reduces the rest") {
  const StateSpace s = modal_system({{0, 0}, {5, 0.05}, {50, 0.05}, {500, 0.05}}, 1, 2, 5);
  const ReducedModel r = balanced_truncation(s, 3);
  CHECK(r.kept_unstable == 1);
  CHECK(r.sys.nx() == 3);
  const Eigen::VectorXcd poles = Eigen::EigenSolver<MatrixXd>(r.sys.A).eigenvalues();
  CHECK(poles.cwiseAbs().minCoeff() < 1e-6);
  CHECK(hinf_difference(s, r.sys, 0.1, 1e4) <= r.error_bound * (1 + 1e-9));
}

TEST_CASE(
    "modal truncation keeps the modes of largest contribution, and the static correction makes the "
    "DC gain exact") {
  // The 80 Hz mode is the weakest (heavily damped, high): it goes first.
  const StateSpace s = modal_system({{3, 0.01}, {20, 0.02}, {80, 0.5}}, 2, 2, 3);
  const auto contributions = modal_contributions(s);
  REQUIRE(contributions.size() == 3);
  CHECK(contributions[0].frequency_hz == Approx(3).epsilon(1e-9));
  CHECK(contributions[2].frequency_hz == Approx(80).epsilon(1e-9));
  CHECK(contributions[2].damping == Approx(0.5).epsilon(1e-9));
  CHECK(contributions[2].contribution < contributions[0].contribution);
  CHECK(contributions[2].contribution < contributions[1].contribution);

  const ReducedModel plain = modal_truncation(s, {.order = 4});
  const ReducedModel corrected = modal_truncation(s, {.order = 4, .dc_correction = true});
  REQUIRE(plain.sys.nx() == 4);
  Eigen::VectorXd kept_hz =
      Eigen::EigenSolver<MatrixXd>(plain.sys.A).eigenvalues().cwiseAbs() / kTwoPi;
  std::sort(kept_hz.data(), kept_hz.data() + kept_hz.size());
  CHECK(kept_hz(0) == Approx(3).epsilon(1e-9));
  CHECK(kept_hz(3) == Approx(20).epsilon(1e-9));

  const MatrixXd dc = (-s.C * s.A.fullPivLu().solve(s.B) + s.D);
  const MatrixXd dc_plain = -plain.sys.C * plain.sys.A.fullPivLu().solve(plain.sys.B) + plain.sys.D;
  const MatrixXd dc_corrected =
      -corrected.sys.C * corrected.sys.A.fullPivLu().solve(corrected.sys.B) + corrected.sys.D;
  CHECK((dc_corrected - dc).norm() <= 1e-12 * dc.norm());
  CHECK((dc_plain - dc).norm() > 1e-3 * dc.norm());
  // Near the kept modes both agree with the full model much better than at DC without the
  // correction (the discarded mode is far above them).
  const auto f = log_frequency_grid_hz(0.5, 25, 200);
  const auto g = frequency_response(s, f), gc = frequency_response(corrected.sys, f);
  for (std::size_t k = 0; k < f.size(); ++k) CHECK((gc[k] - g[k]).norm() <= 0.2 * g[k].norm());

  // By frequency: the modes below 30 Hz.
  CHECK(modal_truncation(s, {.below_hz = 30}).sys.nx() == 4);
}

TEST_CASE("modal truncation keeps a pole at the origin and refuses a defective A") {
  const StateSpace s = modal_system({{0, 0}, {4, 0.02}, {60, 0.02}}, 1, 1, 9);
  const ReducedModel r = modal_truncation(s, {.order = 1});
  CHECK(r.kept_unstable == 1);
  CHECK(r.sys.nx() == 1);
  CHECK(std::abs(r.sys.A(0, 0)) < 1e-6);

  // The floor's double integrator (a Jordan block at the origin) beside two modes: kept whole as
  // one block; the response of the kept part agrees with the full model well below the
  // discarded mode.
  StateSpace floor = modal_system({{4, 0.02}, {60, 0.02}}, 1, 1, 13);
  floor.A.conservativeResize(6, 6);
  floor.A.rightCols(2).setZero();
  floor.A.bottomRows(2).setZero();
  floor.A(4, 5) = 1;  // position' = velocity; velocity' = the input
  floor.A.block(0, 4, 4, 1) = Eigen::VectorXd::Constant(4, 3.0);  // couples the modes to it
  floor.B.conservativeResize(6, 1);
  floor.B.bottomRows(2) << 0, 1;
  floor.C.conservativeResize(1, 6);
  floor.C.rightCols(2) << 0.5, 0;
  floor.states = {"a", "b", "c", "d", "pos", "vel"};
  const ReducedModel kept = modal_truncation(floor, {.order = 4});
  CHECK(kept.kept_unstable == 2);
  REQUIRE(kept.sys.nx() == 4);
  // Expressed in the floor's own states, which only the input drives: they stay, labelled.
  const ReducedModel physical =
      modal_truncation(floor, {.order = 4, .origin_states = {"pos", "vel"}});
  REQUIRE(physical.sys.nx() == 4);
  CHECK(physical.sys.states[0] == "pos");
  CHECK(physical.sys.states[1] == "vel");
  CHECK(std::abs(physical.sys.A(0, 1) - 1) < 1e-12);  // position' = velocity, exactly as before
  CHECK(physical.sys.B.row(1).norm() == Approx(1).epsilon(1e-12));  // velocity' = the input
  const auto fl = log_frequency_grid_hz(0.1, 10, 100);
  const auto gf = frequency_response(floor, fl), gk = frequency_response(kept.sys, fl);
  for (std::size_t k = 0; k < fl.size(); ++k)
    CHECK(std::abs(gk[k](0, 0) - gf[k](0, 0)) <= 0.05 * std::abs(gf[k](0, 0)));

  StateSpace jordan = s;
  jordan.A = MatrixXd::Zero(2, 2);
  jordan.A << -1, 1, 0, -1;
  jordan.B = MatrixXd::Ones(2, 1);
  jordan.C = MatrixXd::Ones(1, 2);
  jordan.D = MatrixXd::Zero(1, 1);
  jordan.states = {"a", "b"};
  CHECK_THROWS_WITH(modal_truncation(jordan, {.order = 1}),
                    Catch::Contains("defective") && Catch::Contains("balanced truncation"));
  CHECK_THROWS_WITH(modal_truncation(s, {}), Catch::Contains("give an order"));
  CHECK_THROWS_AS(balanced_truncation(s, -1), std::invalid_argument);
}
