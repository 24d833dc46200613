// SPDX-License-Identifier: BSD-3-Clause
// doc/design.md §3 validation case 1: spring-mass-damper on a massless cart (seed slides 25-26).
//   A = [0 1; -k/m -d/m], B = [0 0 0; -1 0 0], C = [1 0], D = [0 0 1]  for u = (x1'', x1', x1)
//   G1(s) = x2/x1 = (d/m s + k/m)/(s^2 + d/m s + k/m),  G2(s) = G1(s)/s.
#include <catch2/catch.hpp>
#include <complex>

#include "plant/lti/state_space_builder.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop::plant;

namespace {
constexpr double k = 800.0, d = 4.0, m = 2.0;  // tools/models/cart.toml

std::complex<double> transfer(const lti::StateSpace& ss, int out, const Eigen::VectorXcd& u_of_s,
                              std::complex<double> s) {
  const Eigen::MatrixXcd sI_A =
      s * Eigen::MatrixXcd::Identity(ss.nx(), ss.nx()) - ss.A.cast<std::complex<double>>();
  const Eigen::MatrixXcd G = ss.C.cast<std::complex<double>>() *
                                 sI_A.partialPivLu().solve(ss.B.cast<std::complex<double>>()) +
                             ss.D.cast<std::complex<double>>();
  return (G.row(out) * u_of_s)(0);
}
}  // namespace

TEST_CASE("cart: state space equals the seed's A, B, C, D") {
  const auto model = model::load_model("tools/models/cart.toml");
  const auto lin = model::linearise(model);
  const auto ss =
      lti::build_state_space(model, lin, {"acc:x.1", "vel:x.1", "pos:x.1"}, {"pos:x.2"});
  Eigen::MatrixXd A(2, 2), B(2, 3), C(1, 2), D(1, 3);
  A << 0, 1, -k / m, -d / m;
  B << 0, 0, 0, -1, 0, 0;
  C << 1, 0;
  D << 0, 0, 1;
  CHECK((ss.A - A).norm() <= 1e-12 * A.norm());
  CHECK((ss.B - B).norm() <= 1e-12);
  CHECK((ss.C - C).norm() <= 1e-12);
  CHECK((ss.D - D).norm() <= 1e-12);
  CHECK(ss.states == std::vector<std::string>{"pos:e1.spring", "vel:e1.spring"});
}

TEST_CASE("cart: G1 (position input) and G2 (velocity input) match the seed's transfer functions") {
  const auto model = model::load_model("tools/models/cart.toml");
  const auto lin = model::linearise(model);
  const auto ss =
      lti::build_state_space(model, lin, {"acc:x.1", "vel:x.1", "pos:x.1"}, {"pos:x.2"});
  for (double w : {0.1, 3.0, 20.0, 150.0}) {
    const std::complex<double> s(0.0, w);
    const std::complex<double> g1 = (d / m * s + k / m) / (s * s + d / m * s + k / m);
    Eigen::VectorXcd case1(3), case2(3);
    case1 << s * s, s, 1.0;    // u = (s^2, s, 1) x1
    case2 << s, 1.0, 1.0 / s;  // u = (s, 1, 1/s) v1
    CHECK(std::abs(transfer(ss, 0, case1, s) - g1) <= 1e-12 * std::abs(g1));
    CHECK(std::abs(transfer(ss, 0, case2, s) - g1 / s) <= 1e-12 * std::abs(g1 / s));
  }
}

TEST_CASE(
    "cart: an acceleration-only input needs no integrator states for the dynamics, but the "
    "absolute position output does") {
  const auto model = model::load_model("tools/models/cart.toml");
  const auto lin = model::linearise(model);
  // Relative coordinate output: dynamics do not depend on x1 or x1' (Kdr = Ddr = 0): 2 states.
  const auto rel = lti::build_state_space(model, lin, {"acc:x.1"}, {"pos:e1.spring"});
  CHECK(rel.nx() == 2);
  // Absolute position x2 = x1 + e depends on x1: double integrator appended (seed note 2).
  const auto abs = lti::build_state_space(model, lin, {"acc:x.1"}, {"pos:x.2"});
  REQUIRE(abs.nx() == 4);
  for (double w : {0.5, 20.0, 90.0}) {
    const std::complex<double> s(0.0, w);
    const std::complex<double> g3 =
        (d / m * s + k / m) / (s * s + d / m * s + k / m) / (s * s);  // G1 / s^2
    Eigen::VectorXcd one(1);
    one << 1.0;
    CHECK(std::abs(transfer(abs, 0, one, s) - g3) <= 1e-10 * std::abs(g3));
  }
}
