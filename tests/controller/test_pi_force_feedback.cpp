// SPDX-License-Identifier: BSD-3-Clause
// PI force feedback on the metrology frame (doc/design.md §4, seed slides 31-33): the closed-loop
// poles land where the design puts them, the state-space loop equals the frequency-wise formula
// for T, and the sampled loop equals a step-by-step run of the loop it models.
#include <catch2/catch.hpp>

#include <algorithm>
#include <complex>
#include <numbers>
#include <random>

#include "numeric/constants.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/feedback_interconnection.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "tests/support/metrology.hpp"
#include "tests/support/pole_matching.hpp"

using namespace flexloop;
using cd = std::complex<double>;

namespace {

using flexloop::numeric::kTwoPi;

// Roots of the per-mode closed-loop cubic (an independent route: polynomial roots, no matrices).
std::vector<cd> mode_roots(const controller::design::PiForceFeedbackSettings& s) {
  return test::polynomial_roots(controller::design::closed_loop_mode_polynomial(s));
}

using test::match_poles;

}  // namespace

TEST_CASE(
    "PI force feedback: undamped equal struts put six pole pairs at s^2 + 2 zeta w_d s + "
    "w_d^2 and six poles at s = 0",
    "[controller][pi]") {
  auto sc = scene::load_scene(test::metrology_scene_path());
  sc.controller.leak_hz = 0;
  const auto p = scene::build_scene_plant(sc, {.without_damping = true});
  const auto& s = p.gains.settings;
  const Eigen::VectorXcd poles = plant::lti::poles(p.closed_loop);
  REQUIRE(poles.size() == 18);
  const double wd = s.omega_d_rad_s, z = s.zeta;
  const cd pair(-z * wd, wd * std::sqrt(1 - z * z));
  const double err = match_poles(poles, {pair, std::conj(pair)}, 6, std::abs(pair));
  const double err0 = match_poles(poles, {cd(0, 0)}, 6, wd);
  INFO("pairs: worst relative error " << err << "; zeros: worst |s|/w_d " << err0);
  CHECK(err <= 1e-8);
  CHECK(err0 <= 1e-8);
}

TEST_CASE(
    "PI force feedback: the leak moves the integrator poles into the left half plane as "
    "the mode cubic predicts",
    "[controller][pi]") {
  for (double leak_hz : {0.1, 1.0, 3.0}) {
    auto sc = scene::load_scene(test::metrology_scene_path());
    sc.controller.leak_hz = leak_hz;
    const auto p = scene::build_scene_plant(sc, {.without_damping = true});
    const auto roots = mode_roots(p.gains.settings);
    const Eigen::VectorXcd poles = plant::lti::poles(p.closed_loop);
    const double err = match_poles(poles, roots, 6, p.gains.settings.omega_d_rad_s);
    INFO("leak " << leak_hz << " Hz: worst error / w_d " << err);
    CHECK(err <= 1e-8);
    CHECK(poles.real().maxCoeff() < 0);
  }
}

TEST_CASE(
    "PI force feedback: the state-space closed loop equals T = G11 + G12 C (I - G22 C)^-1 "
    "G21 frequency by frequency",
    "[controller][pi]") {
  for (double leak_hz : {0.0, 0.5}) {
    auto sc = scene::load_scene(test::metrology_scene_path());
    sc.controller.leak_hz = leak_hz;
    const auto p = scene::build_scene_plant(sc);
    const std::vector<double> f = {0.013, 0.1, 1.0, 7.5, 13.9, 20.0, 31.3, 49.0, 120.0, 900.0};
    const auto G = plant::lti::frequency_response(p.plant, f);
    const auto C = plant::lti::frequency_response(p.controller, f);
    const auto T = plant::lti::frequency_response(p.closed_loop, f);
    double worst = 0;
    for (std::size_t k = 0; k < f.size(); ++k) {
      const Eigen::MatrixXcd ref = plant::lti::lft_closed_loop(G[k], C[k], p.partition);
      worst = std::max(worst, (T[k] - ref).norm() / ref.norm());
    }
    INFO("leak " << leak_hz << " Hz: worst relative difference " << worst);
    CHECK(worst <= 1e-10);
  }
}

TEST_CASE("the sampled closed loop equals a step-by-step run of plant and controller",
          "[controller][pi][discrete]") {
  auto sc = scene::load_scene(test::metrology_scene_path());
  sc.controller.leak_hz = 0.2;
  const auto p = scene::build_scene_plant(sc);
  const auto s = scene::sample_scene(p);
  const auto& P = s.plant.sys;
  const auto& K = s.controller.sys;
  const auto& T = s.closed_loop.sys;
  const Eigen::Index nw = p.partition.disturbances, nz = p.partition.performance;
  const Eigen::Index nu = P.nu() - nw;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(P.nx()), xc = Eigen::VectorXd::Zero(K.nx()),
                  u_held = Eigen::VectorXd::Zero(nu), xt = Eigen::VectorXd::Zero(T.nx());
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1e-3);
  double worst = 0, scale = 0;
  for (int k = 0; k < 5000; ++k) {
    Eigen::VectorXd w(nw);
    for (auto& v : w) v = n(rng);
    // The loop as the simulation runs it: sensors see the held command; the controller removes
    // it (f = y - u_held), solves its algebraic loop with D22 = I, holds the answer.
    Eigen::VectorXd in(P.nu());
    in << w, u_held;
    const Eigen::VectorXd out = P.C * x + P.D * in;
    const Eigen::VectorXd f = out.tail(P.ny() - nz) - u_held;
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(nu, nu);
    const Eigen::VectorXd u = (I - K.D).partialPivLu().solve(K.C * xc + K.D * f);
    Eigen::VectorXd in_now(P.nu());
    in_now << w, u;
    x = P.A * x + P.B * in_now;
    xc = K.A * xc + K.B * (f + u);
    u_held = u;
    // The closed-loop state space.
    const Eigen::VectorXd zt = T.C * xt + T.D * w;
    xt = T.A * xt + T.B * w;
    worst = std::max(worst, (zt - out.head(nz)).cwiseAbs().maxCoeff());
    scale = std::max(scale, out.head(nz).cwiseAbs().maxCoeff());
  }
  INFO("worst difference " << worst << " of " << scale);
  CHECK(worst <= 1e-12 * scale);
  CHECK(s.closed_loop.spectral_radius < 1.0);
  // The sensors' feedthrough D22 is the identity (sigma_1 = sigma_a + ...), which is what the
  // loop above assumed.
  CHECK((P.D.bottomRightCorner(nu, nu) - Eigen::MatrixXd::Identity(nu, nu)).norm() <= 1e-12);
}
