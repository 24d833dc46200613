// SPDX-License-Identifier: BSD-3-Clause
// The stability guard, input checks and method names.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "numeric/constants.hpp"
#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"

using namespace flexloop::plant::lti;
using namespace flexloop::test;
using Catch::Matchers::Contains;

namespace {

using flexloop::numeric::kTwoPi;

// A slow well-damped mode plus a stiff lightly damped 2 kHz mode (structural), one input.
StateSpace stiff_plant(double f_stiff = 2000, double zeta_stiff = 0.02) {
  const double w1 = kTwoPi * 5, z1 = 0.3, w2 = kTwoPi * f_stiff;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4, 4), B(4, 1), C(1, 4), D(1, 1);
  A(0, 1) = 1;
  A(1, 0) = -w1 * w1;
  A(1, 1) = -2 * z1 * w1;
  A(2, 3) = 1;
  A(3, 2) = -w2 * w2;
  A(3, 3) = -2 * zeta_stiff * w2;
  B << 0, 1, 0, 1;
  C << 1, 0, 1, 0;
  D << 0;
  return labelled(A, B, C, D);
}

std::string refusal_message(const StateSpace& c, const DiscretisationOptions& o) {
  try {
    discretise(c, o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST_CASE("forward euler on a stiff lightly damped mode is refused, with the way out") {
  const auto plant = stiff_plant();
  const double dt = 1e-3;  // 1 kHz sampling of a 2 kHz mode
  const std::string msg =
      refusal_message(plant, {.method = DiscretisationMethod::kForwardEuler, .dt = dt});
  INFO(msg);
  REQUIRE_FALSE(msg.empty());
  CHECK_THAT(msg, Contains("euler"));
  CHECK_THAT(msg, Contains("2000 Hz"));  // the offending mode
  CHECK_THAT(msg, Contains("0.001"));    // the sample time
  CHECK_THAT(msg, Contains("zoh"));
  CHECK_THAT(msg, Contains("tustin"));
  CHECK_THAT(msg, Contains("rate above"));

  // Forced: kept, and the spectral radius is |1 + λT| of the stiff pole.
  const auto forced =
      discretise(plant, {.method = DiscretisationMethod::kForwardEuler, .dt = dt, .force = true});
  const double w = kTwoPi * 2000, zeta = 0.02;
  const cd lambda(-zeta * w, w * std::sqrt(1 - zeta * zeta));
  CHECK(forced.spectral_radius == Approx(std::abs(1.0 + lambda * dt)).epsilon(1e-10));
  CHECK(forced.spectral_radius > 1);

  // Backward euler, zoh, foh and tustin keep it stable at the same rate.
  const auto back = discretise(plant, {.method = DiscretisationMethod::kBackwardEuler, .dt = dt});
  CHECK(back.spectral_radius < 1);
  // Its spectral radius is max |1/(1 - λT)| over both modes (the slow one dominates).
  const double w1 = kTwoPi * 5, z1 = 0.3;
  const cd slow(-z1 * w1, w1 * std::sqrt(1 - z1 * z1));
  CHECK(back.spectral_radius ==
        Approx(std::max(std::abs(1.0 / (1.0 - lambda * dt)), std::abs(1.0 / (1.0 - slow * dt))))
            .epsilon(1e-10));
  for (const auto m : {DiscretisationMethod::kZeroOrderHold, DiscretisationMethod::kFirstOrderHold,
                       DiscretisationMethod::kTustin})
    CHECK(discretise(plant, {.method = m, .dt = dt}).spectral_radius < 1);
}

TEST_CASE("forward euler is accepted just above the rate the message names, refused below") {
  const auto plant = stiff_plant();
  // |1 + λT| <= 1 needs T <= 2ζ/ωn: a rate above ωn / (2ζ). The slow mode needs far less.
  const double needed = kTwoPi * 2000 / (2 * 0.02);
  const auto ok =
      discretise(plant, {.method = DiscretisationMethod::kForwardEuler, .dt = 1 / (1.01 * needed)});
  CHECK(ok.spectral_radius <= 1);
  const std::string msg = refusal_message(
      plant, {.method = DiscretisationMethod::kForwardEuler, .dt = 1 / (0.99 * needed)});
  INFO(msg);
  CHECK_THAT(msg, Contains("rate above"));
  // The named rate is the threshold itself (printed with 6 significant digits).
  char expected[32];
  std::snprintf(expected, sizeof expected, "%.6g Hz", needed);
  CHECK_THAT(msg, Contains(expected));
}

TEST_CASE("undamped modes: euler has no stable rate, zoh keeps |z| = 1, unstable plants pass") {
  const double w = kTwoPi * 50;
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << 0, 1, -w * w, 0;
  B << 0, 1;
  C << 1, 0;
  D << 0;
  const auto osc = labelled(A, B, C, D);
  const std::string msg =
      refusal_message(osc, {.method = DiscretisationMethod::kForwardEuler, .dt = 1e-4});
  INFO(msg);
  CHECK_THAT(msg, Contains("no rate makes euler stable"));
  CHECK(discretise(osc, {.method = DiscretisationMethod::kZeroOrderHold, .dt = 1e-4})
            .spectral_radius == Approx(1.0).epsilon(1e-12));
  CHECK(discretise(osc, {.method = DiscretisationMethod::kTustin, .dt = 1e-4}).spectral_radius ==
        Approx(1.0).epsilon(1e-12));

  // An unstable continuous plant is not the guard's business: its discrete form is unstable.
  Eigen::MatrixXd Au(1, 1), Bu(1, 1), Cu(1, 1), Du(1, 1);
  Au << 10.0;
  Bu << 1;
  Cu << 1;
  Du << 0;
  const auto d = discretise(labelled(Au, Bu, Cu, Du),
                            {.method = DiscretisationMethod::kForwardEuler, .dt = 1e-3});
  CHECK(d.spectral_radius == Approx(1.01).epsilon(1e-12));
}

TEST_CASE("rigid-body modes in general coordinates are not mistaken for instability") {
  // Two free masses (Jordan blocks at 0, computed only to ~sqrt(eps ||A||), so eig(Ad) lands at
  // 1 + 1e-6 or so) and a 2 kHz structural mode, in random well-conditioned coordinates.
  std::mt19937 rng(99);
  const double w = kTwoPi * 2000, zeta = 0.02;
  int above_one = 0;  // results whose computed radius exceeds 1 + 1e-9 by round-off alone
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, 6);
    J(0, 1) = 1;
    J(2, 3) = 1;
    J(4, 5) = 1;
    J(5, 4) = -w * w;
    J(5, 5) = -2 * zeta * w;
    const Eigen::MatrixXd S = random_matrix(rng, 6, 6) + 3 * Eigen::MatrixXd::Identity(6, 6);
    const Eigen::MatrixXd Sinv = S.partialPivLu().inverse();
    const auto plant = labelled(S * J * Sinv, S * random_matrix(rng, 6, 2),
                                random_matrix(rng, 2, 6) * Sinv, Eigen::MatrixXd::Zero(2, 2));
    INFO("trial " << trial);
    for (const auto m :
         {DiscretisationMethod::kZeroOrderHold, DiscretisationMethod::kFirstOrderHold,
          DiscretisationMethod::kTustin, DiscretisationMethod::kBackwardEuler}) {
      const auto d = discretise(plant, {.method = m, .dt = 1e-4});
      CHECK(d.spectral_radius == Approx(1.0).margin(1e-4));
      if (d.spectral_radius > 1 + 1e-9) ++above_one;
    }
    // The stiff mode still makes forward Euler at 10 kHz unstable: refused, naming it.
    CHECK_THROWS_WITH(
        discretise(plant, {.method = DiscretisationMethod::kForwardEuler, .dt = 1e-4}),
        Contains("2000 Hz") && Contains("rate above"));
  }
  CHECK(above_one > 0);  // the case the guard must tolerate did occur
}

TEST_CASE("bad options and systems are rejected with std::invalid_argument") {
  const auto plant = stiff_plant();
  const auto nan = std::numeric_limits<double>::quiet_NaN();
  const auto inf = std::numeric_limits<double>::infinity();
  using M = DiscretisationMethod;
  CHECK_THROWS_AS(discretise(plant, {.method = M::kZeroOrderHold, .dt = 0}), std::invalid_argument);
  CHECK_THROWS_AS(discretise(plant, {.method = M::kZeroOrderHold, .dt = -1e-3}),
                  std::invalid_argument);
  CHECK_THROWS_AS(discretise(plant, {.method = M::kZeroOrderHold, .dt = nan}),
                  std::invalid_argument);
  CHECK_THROWS_AS(discretise(plant, {.method = M::kZeroOrderHold, .dt = inf}),
                  std::invalid_argument);
  // Pre-warping: tustin only, finite, positive, below Nyquist.
  CHECK_THROWS_WITH(discretise(plant, {.method = M::kZeroOrderHold, .dt = 1e-3, .prewarp_hz = 10}),
                    Contains("tustin only"));
  CHECK_THROWS_WITH(discretise(plant, {.method = M::kTustin, .dt = 1e-3, .prewarp_hz = 500}),
                    Contains("Nyquist"));
  CHECK_THROWS_AS(discretise(plant, {.method = M::kTustin, .dt = 1e-3, .prewarp_hz = -1}),
                  std::invalid_argument);
  CHECK_THROWS_AS(discretise(plant, {.method = M::kTustin, .dt = 1e-3, .prewarp_hz = nan}),
                  std::invalid_argument);

  auto bad = plant;
  bad.A(1, 1) = nan;
  CHECK_THROWS_AS(discretise(bad, {.method = M::kZeroOrderHold, .dt = 1e-3}),
                  std::invalid_argument);
  auto wrong = plant;
  wrong.B = Eigen::MatrixXd::Zero(3, 1);
  CHECK_THROWS_AS(discretise(wrong, {.method = M::kZeroOrderHold, .dt = 1e-3}),
                  std::invalid_argument);

  // Tustin cannot map a continuous pole at s = 2/T (it would go to z = infinity).
  Eigen::MatrixXd A(1, 1), B(1, 1), C(1, 1), D(1, 1);
  A << 2000.0;
  B << 1;
  C << 1;
  D << 0;
  CHECK_THROWS_WITH(discretise(labelled(A, B, C, D), {.method = M::kTustin, .dt = 1e-3}),
                    Contains("singular"));
}

TEST_CASE("a static gain (no states) keeps D under every method") {
  Eigen::MatrixXd D(2, 3);
  D << 1, 2, 3, 4, 5, 6;
  const auto gain =
      labelled(Eigen::MatrixXd(0, 0), Eigen::MatrixXd(0, 3), Eigen::MatrixXd(2, 0), D);
  for (const auto m : {DiscretisationMethod::kZeroOrderHold, DiscretisationMethod::kFirstOrderHold,
                       DiscretisationMethod::kTustin, DiscretisationMethod::kForwardEuler,
                       DiscretisationMethod::kBackwardEuler}) {
    const auto d = discretise(gain, {.method = m, .dt = 1e-3});
    CHECK(d.sys.nx() == 0);
    CHECK(d.sys.B.cols() == 3);
    CHECK(d.sys.C.rows() == 2);
    CHECK(d.sys.D == D);
    CHECK(d.spectral_radius == 0);
  }
}

TEST_CASE("method names parse and print, unknown names list the valid ones") {
  for (const char* name : {"zoh", "foh", "tustin", "euler", "backward-euler"})
    CHECK(to_string(parse_discretisation_method(name)) == name);
  CHECK_THROWS_WITH(parse_discretisation_method("bilinear"),
                    Contains("bilinear") && Contains("zoh, foh, tustin, euler, backward-euler"));
}
