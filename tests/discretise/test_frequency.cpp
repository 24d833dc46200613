// SPDX-License-Identifier: BSD-3-Clause
// Pole maps and frequency responses: H_d(z) = Cd (zI - Ad)^-1 Bd + Dd by a linear solve, compared
// with the continuous H_c(s) = C (sI - A)^-1 B + D at the s each method substitutes for z.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "numeric/constants.hpp"
#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"

using namespace flexloop::plant::lti;
using namespace flexloop::test;

namespace {

using flexloop::numeric::kTwoPi;

Eigen::MatrixXcd hc(const StateSpace& c, cd s) {
  return frequency_response(c.A, c.B, c.C, c.D, s);
}
Eigen::MatrixXcd hd(const DiscreteStateSpace& d, cd z) {
  return frequency_response(d.sys.A, d.sys.B, d.sys.C, d.sys.D, z);
}

// Every expected discrete pole has a computed eigenvalue of Ad within tol (relative to |z|).
void check_poles(const Eigen::MatrixXd& Ad, const std::vector<cd>& expected, double tol) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(Ad, false);
  const Eigen::VectorXcd got = es.eigenvalues();
  REQUIRE(static_cast<std::size_t>(got.size()) == expected.size());
  for (const auto& z : expected) {
    double best = INFINITY;
    for (const auto& g : got) best = std::min(best, std::abs(g - z));
    INFO("expected pole " << z << ", nearest at distance " << best);
    CHECK(best <= tol * std::max(1.0, std::abs(z)));
  }
}

}  // namespace

TEST_CASE("pole maps: zoh e^{sT}, tustin (1+sT/2)/(1-sT/2), euler 1+sT, backward 1/(1-sT)") {
  const auto sys = make_modal_system(11);
  const double dt = 1e-3;
  struct Case {
    DiscretisationMethod method;
    cd (*map)(cd, double);
  };
  const Case cases[] = {
      {DiscretisationMethod::kZeroOrderHold, [](cd s, double T) { return std::exp(s * T); }},
      {DiscretisationMethod::kFirstOrderHold, [](cd s, double T) { return std::exp(s * T); }},
      {DiscretisationMethod::kTustin,
       [](cd s, double T) { return (1.0 + s * T / 2.0) / (1.0 - s * T / 2.0); }},
      {DiscretisationMethod::kForwardEuler, [](cd s, double T) { return 1.0 + s * T; }},
      {DiscretisationMethod::kBackwardEuler, [](cd s, double T) { return 1.0 / (1.0 - s * T); }},
  };
  for (const auto& c : cases) {
    DYNAMIC_SECTION(to_string(c.method)) {
      // force: forward Euler at this rate is unstable for the 140 Hz mode; the map still holds.
      const auto d = discretise(sys.ss, {.method = c.method, .dt = dt, .force = true});
      std::vector<cd> expected;
      double rho = 0;
      for (const auto& s : sys.eigenvalues()) {
        expected.push_back(c.map(s, dt));
        rho = std::max(rho, std::abs(expected.back()));
      }
      check_poles(d.sys.A, expected, 1e-10);
      CHECK(d.spectral_radius == Approx(rho).epsilon(1e-10));
    }
  }
}

TEST_CASE("tustin, euler, backward euler: H_d(z) equals H_c at the substituted s exactly") {
  // Tests all four matrices of each method, not just the poles.
  const auto sys = make_modal_system(5);
  const double dt = 1e-3;
  for (const double f : {0.3, 7.0, 61.0, 140.0, 333.0, 499.0}) {
    const cd z = std::exp(cd(0.0, kTwoPi * f * dt));
    const auto tustin = discretise(sys.ss, {.method = DiscretisationMethod::kTustin, .dt = dt});
    // force: forward Euler is unstable here for the 140 Hz mode; the identity still holds.
    const auto euler = discretise(
        sys.ss, {.method = DiscretisationMethod::kForwardEuler, .dt = dt, .force = true});
    const auto back =
        discretise(sys.ss, {.method = DiscretisationMethod::kBackwardEuler, .dt = dt});
    INFO("f = " << f << " Hz");
    CHECK(relative_difference(hd(tustin, z), hc(sys.ss, (2.0 / dt) * (z - 1.0) / (z + 1.0))) <=
          1e-10);
    CHECK(relative_difference(hd(euler, z), hc(sys.ss, (z - 1.0) / dt)) <= 1e-10);
    CHECK(relative_difference(hd(back, z), hc(sys.ss, (z - 1.0) / (z * dt))) <= 1e-10);
  }
}

TEST_CASE("tustin with pre-warping matches the continuous response exactly at f0") {
  const auto sys = make_modal_system(9);
  const double dt = 1e-3;
  for (const double f0 : {61.0, 140.0, 250.0, 400.0}) {
    const cd z0 = std::exp(cd(0.0, kTwoPi * f0 * dt));
    const Eigen::MatrixXcd want = hc(sys.ss, cd(0.0, kTwoPi * f0));
    const auto warped =
        discretise(sys.ss, {.method = DiscretisationMethod::kTustin, .dt = dt, .prewarp_hz = f0});
    const auto plain = discretise(sys.ss, {.method = DiscretisationMethod::kTustin, .dt = dt});
    const double err_warped = relative_difference(hd(warped, z0), want);
    const double err_plain = relative_difference(hd(plain, z0), want);
    INFO("f0 = " << f0 << " Hz: pre-warped " << err_warped << ", plain " << err_plain);
    CHECK(err_warped <= 1e-10);
    CHECK(err_plain > 1e-4);  // pre-warping is what makes the match
    CHECK(warped.prewarp_hz == f0);
  }
}

TEST_CASE("every method's frequency response approaches the continuous one at low frequency") {
  // A 12-state plant whose slowest mode is 1.3 Hz, sampled at 1 kHz; compare well below it.
  const auto sys = make_modal_system(3);
  const double dt = 1e-3;
  for (const auto method :
       {DiscretisationMethod::kZeroOrderHold, DiscretisationMethod::kFirstOrderHold,
        DiscretisationMethod::kTustin, DiscretisationMethod::kForwardEuler,
        DiscretisationMethod::kBackwardEuler}) {
    DYNAMIC_SECTION(to_string(method)) {
      // force: forward Euler is unstable here for the 140 Hz mode, yet converges at low frequency.
      const auto d = discretise(sys.ss, {.method = method, .dt = dt, .force = true});
      std::vector<double> err;
      for (const double f : {0.1, 0.01, 0.001}) {
        const cd z = std::exp(cd(0.0, kTwoPi * f * dt));
        err.push_back(relative_difference(hd(d, z), hc(sys.ss, cd(0.0, kTwoPi * f))));
      }
      INFO("relative error at 0.1, 0.01, 0.001 Hz: " << err[0] << ", " << err[1] << ", " << err[2]);
      CHECK(err[0] < 1e-2);
      // At least first-order convergence per decade (zoh and euler are first order: the hold's
      // half-sample delay; foh and tustin are second order).
      CHECK(err[1] < err[0] / 5);
      CHECK(err[2] < std::max(err[1] / 5, 1e-9));
      // DC gain: exact for zoh, foh, tustin and both Eulers (z = 1 <-> s = 0).
      CHECK(relative_difference(hd(d, 1.0), hc(sys.ss, 0.0)) <= 1e-9);
    }
  }
}
