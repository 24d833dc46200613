// SPDX-License-Identifier: BSD-3-Clause
// Integral force feedback on the gravity-loaded metrology frame (doc/design.md §4, §9;
// controller/design/loop_stability.hpp). The struts carry the weight in compression, so the
// preload's geometric stiffness Gdd has negative directions; a pure integrator removes the struts'
// static stiffness and the frame drifts away along them. Checked against the per-direction cubic
//   (s^2 + g_i)(s + w_l + 2 zeta w_d) + w_d^2 (s + w_l) = 0,   g_i = eig(Mdd^-1 Gdd),
// (polynomial roots: an independent route) and its stability bound on the leak.
#include <catch2/catch.hpp>

#include <complex>
#include <numbers>

#include "common/input_error.hpp"
#include "controller/design/loop_stability.hpp"
#include "numeric/constants.hpp"
#include "offline/scene/scene_plant.hpp"
#include "tests/support/pole_matching.hpp"

using namespace flexloop;
using cd = std::complex<double>;

namespace {

using flexloop::numeric::kTwoPi;

scene::ScenePlant preloaded(double leak_hz, bool damped) {
  auto sc = scene::load_scene("tools/scenes/metrology_frame.toml");
  sc.gravity_preload = true;
  sc.controller.leak_hz = leak_hz;
  return scene::build_scene_plant(sc, {.without_damping = !damped});
}

Eigen::VectorXd g_per_mass(const scene::ScenePlant& p) {
  const int nd = p.model.nd();
  return controller::design::geometric_stiffness_per_mass(p.lin.M.topLeftCorner(nd, nd),
                                                          p.lin.G.topLeftCorner(nd, nd));
}

}  // namespace

TEST_CASE(
    "gravity preload, undamped equal struts: the loop's poles are the roots of (s^2 + g_i)(s + "
    "w_l + 2 zeta w_d) + w_d^2 (s + w_l), g_i = eig(Mdd^-1 Gdd)",
    "[controller][preload]") {
  for (double leak_hz : {0.0, 0.2, 1.0}) {
    const auto p = preloaded(leak_hz, false);
    const auto& s = p.gains.settings;
    const double wd = s.omega_d_rad_s, a = s.leak_rad_s + 2 * s.zeta * wd;
    const Eigen::VectorXd g = g_per_mass(p);
    std::vector<cd> roots;
    for (double gi : g) {
      const auto r = test::polynomial_roots(
          std::array<double, 4>{1.0, a, gi + wd * wd, gi * a + wd * wd * s.leak_rad_s});
      roots.insert(roots.end(), r.begin(), r.end());
    }
    REQUIRE(p.loop.poles.size() == 18);  // 12 suspension + 6 controller states, no floor states
    const double err = test::match_poles(p.loop.poles, roots, 1, wd);
    INFO("leak " << leak_hz << " Hz: g_i [rad^2/s^2] = " << g.transpose()
                 << "; worst pole error / w_d " << err << "; largest Re s "
                 << p.loop.largest_real_part);
    CHECK(err <= 1e-8);
    // Without a leak every negative g_i gives one real pole in the right half plane.
    if (leak_hz == 0) CHECK(p.loop.unstable == (g.array() < 0).count());
  }
}

TEST_CASE("gravity preload: the compressed struts make Gdd negative in every direction here",
          "[controller][preload]") {
  // Not an assumption of the code, a property of this machine worth knowing: all six g_i < 0
  // (the frame sits on its struts like an inverted pendulum in every direction), all tiny
  // against the suspension's own stiffness (w_1^2 = (2 pi 13.9 Hz)^2 = 7.6e3 rad^2/s^2).
  const Eigen::VectorXd g = g_per_mass(preloaded(0.0, false));
  INFO("g_i = " << g.transpose());
  CHECK(g.maxCoeff() < 0);
  CHECK(-g.minCoeff() < 0.05 * std::pow(kTwoPi * 13.9, 2));
}

TEST_CASE(
    "gravity preload: the smallest stable leak found on the loop's poles equals the "
    "equal-strut bound max 2 zeta w_d (-g_i) / (w_d^2 + g_i)",
    "[controller][preload]") {
  const auto undamped = preloaded(0.0, false);
  const int nd = undamped.model.nd();
  const double bound = controller::design::equal_strut_minimum_leak_rad_s(
      undamped.lin.M.topLeftCorner(nd, nd), undamped.lin.G.topLeftCorner(nd, nd),
      undamped.gains.settings);
  const auto found = scene::minimum_stable_leak_hz(undamped);
  REQUIRE(found);
  INFO("bound " << bound / kTwoPi << " Hz, bisection " << *found << " Hz");
  CHECK(bound > 0);
  CHECK(*found * kTwoPi == Approx(bound).epsilon(1e-5));

  // The real (damped) struts: damping of 0.2 % moves the bound a little; either side of it the
  // loop is unstable and stable.
  const auto damped = preloaded(0.0, true);
  const auto leak = scene::minimum_stable_leak_hz(damped);
  REQUIRE(leak);
  INFO("damped: smallest stable leak " << *leak << " Hz");
  CHECK(*leak == Approx(bound / kTwoPi).epsilon(0.1));
  CHECK_FALSE(preloaded(0.95 * *leak, true).loop.stable());
  CHECK(preloaded(1.05 * *leak, true).loop.stable());
}

TEST_CASE(
    "an unstable loop is refused by the loop commands at the scene's leak_hz line, with the "
    "leak that would make it stable",
    "[controller][preload]") {
  const std::string text = R"(
[scene]
name = "preload without leak"
model = "../models/metrology_frame.toml"
[plant]
gravity_preload = true
disturbances = ["acc:x.9", "acc:z.11", "acc:y.13", "acc:z.15", "acc:z.17", "acc:y.19"]
actuators = ["stress:e1.4", "stress:e1.5", "stress:e1.6", "stress:e1.7", "stress:e1.8", "stress:e1.9"]
performance = ["acc:x.3", "acc:z.3", "acc:y.5", "acc:z.5", "acc:z.7", "acc:y.7"]
sensors = ["stress:e1.4", "stress:e1.5", "stress:e1.6", "stress:e1.7", "stress:e1.8", "stress:e1.9"]
[controller]
omega_d_hz = 10.0
leak_hz = 0.0
)";
  const auto sc = scene::parse_scene(text, "tools/scenes/preload_without_leak.toml");
  const auto p = scene::build_scene_plant(sc);
  CHECK_FALSE(p.loop.stable());
  try {
    scene::require_stable_loop(p);
    FAIL("an unstable loop was accepted");
  } catch (const common::InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.rfind("tools/scenes/preload_without_leak.toml:13: [controller]: the closed loop is "
                     "unstable",
                     0) == 0);
    CHECK(what.find("a leak_hz of at least 0.3") != std::string::npos);
  }
  // With the leak above the bound the same scene is accepted.
  auto fixed = sc;
  fixed.controller.leak_hz = 1.0;
  CHECK_NOTHROW(scene::require_stable_loop(scene::build_scene_plant(fixed)));
}
