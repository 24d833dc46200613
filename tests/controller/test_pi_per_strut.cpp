// SPDX-License-Identifier: BSD-3-Clause
// PI force feedback designed per strut (controller/design/pi_force_feedback.hpp): one loop per
// collocated actuator and force sensor, for any number of struts. On the metrology frame the
// scene keeps the coupled rule (its gains bitwise) and the per-strut rule is that rule's diagonal;
// with equal struts every mode obeys the per-strut cubic; box8 (8 struts, 6 degrees of freedom,
// tests/fixtures/box8.toml) is accepted, stable, and every mode damped more than open loop; an
// actuator without its collocated force sensor is refused at the scene's entry.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <complex>
#include <string>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "offline/scene/collocated_struts.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/pole_text.hpp"
#include "tests/support/metrology.hpp"
#include "tests/support/pole_matching.hpp"

using namespace flexloop;
using controller::design::PiForceFeedbackSettings;

namespace {

using flexloop::numeric::kTwoPi;

const char* const kBox8Scene = "tests/fixtures/box8.toml";

// Damping ratio -Re s / |s| of the poles that are not integrators (s = 0 within round-off).
std::vector<double> damping_ratios(const Eigen::VectorXcd& poles) {
  const double at_zero = plant::lti::integrator_tolerance(poles);
  std::vector<double> zeta;
  for (const auto& s : poles)
    if (!plant::lti::is_integrator(s, at_zero)) zeta.push_back(-s.real() / std::abs(s));
  return zeta;
}

PiForceFeedbackSettings scene_settings(const scene::Scene& sc) {
  return {kTwoPi * sc.controller.omega_d_hz, sc.controller.zeta, kTwoPi * sc.controller.leak_hz};
}

}  // namespace

TEST_CASE("PI per strut: one strut on one mass gets the coupled rule's gains",
          "[controller][pi][per_strut]") {
  const double m = 3.5, k = 2.0e6;
  const PiForceFeedbackSettings s{kTwoPi * 12.0, 0.4, kTwoPi * 0.5};
  const auto coupled = controller::design::design_pi_force_feedback(
      Eigen::MatrixXd::Constant(1, 1, m), Eigen::MatrixXd::Constant(1, 1, k), s);
  const auto per_strut = controller::design::design_pi_force_feedback_per_strut({{k, 1.0 / m}}, s);
  CHECK(std::abs(per_strut.K_P(0, 0) - coupled.K_P(0, 0)) <= 1e-14 * std::abs(coupled.K_P(0, 0)));
  CHECK(std::abs(per_strut.K_I(0, 0) - coupled.K_I(0, 0)) <= 1e-14 * std::abs(coupled.K_I(0, 0)));
  // K_P = k / (m w_d^2) - 1 by hand.
  CHECK(std::abs(per_strut.K_P(0, 0) - (k / (m * s.omega_d_rad_s * s.omega_d_rad_s) - 1)) <=
        1e-14 * per_strut.K_P(0, 0));
  CHECK_THROWS_AS(controller::design::design_pi_force_feedback_per_strut({{k, 0.0}}, s),
                  std::invalid_argument);
  CHECK_THROWS_AS(controller::design::design_pi_force_feedback_per_strut({}, s),
                  std::invalid_argument);
}

TEST_CASE(
    "PI per strut: the metrology frame keeps the coupled rule bitwise, and per strut it is that "
    "rule's diagonal",
    "[controller][pi][per_strut][metrology]") {
  const auto& p = test::metrology().p;
  REQUIRE(p.struts.empty());  // the struts are the dynamic coordinates: the seed's coupled rule
  const Eigen::MatrixXd Mdd = p.lin.M.topLeftCorner(6, 6), Kdd = p.lin.K.topLeftCorner(6, 6);
  const auto s = scene_settings(p.scene);
  const auto coupled = controller::design::design_pi_force_feedback(Mdd, Kdd, s);
  CHECK(p.gains.K_P == coupled.K_P);
  CHECK(p.gains.K_I == coupled.K_I);
  // The coupled K_P is full; per strut keeps its diagonal (b_i a unit vector, Kdd = k I).
  const auto struts = scene::collocated_struts(p.scene, p.model, p.lin);
  REQUIRE(struts.size() == 6);
  const auto per_strut = controller::design::design_pi_force_feedback_per_strut(struts, s);
  const double scale = coupled.K_P.diagonal().cwiseAbs().maxCoeff();
  CHECK((per_strut.K_P.diagonal() - coupled.K_P.diagonal()).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  CHECK((per_strut.K_I.diagonal() - coupled.K_I.diagonal()).cwiseAbs().maxCoeff() <=
        1e-12 * coupled.K_I.diagonal().cwiseAbs().maxCoeff());
  CHECK(Eigen::MatrixXd(per_strut.K_P.diagonal().asDiagonal()) == per_strut.K_P);
  // 1/m_i by its definition, the diagonal of Mdd^-1 (here b_i is the i-th unit vector).
  const Eigen::MatrixXd Minv = Mdd.inverse();
  for (int i = 0; i < 6; ++i) {
    CHECK(std::abs(struts[static_cast<std::size_t>(i)].inverse_mass - Minv(i, i)) <=
          1e-12 * Minv(i, i));
    CHECK(struts[static_cast<std::size_t>(i)].stiffness == Kdd(i, i));
  }
}

TEST_CASE(
    "PI per strut: equal undamped struts, the only stiffness, put every mode on "
    "s^2 (1 + K_P)(s + w_l + 2 zeta w_d) + w_j^2 (s + w_l) = 0",
    "[controller][pi][per_strut]") {
  auto sc = scene::load_scene(test::metrology_scene_path());
  sc.controller.leak_hz = 0.5;
  const auto p = scene::build_scene_plant(sc, {.without_damping = true});
  const auto s = scene_settings(sc);
  const auto gains = controller::design::design_pi_force_feedback_per_strut(
      scene::collocated_struts(sc, p.model, p.lin), s);
  // The three-fold symmetry makes the six struts alike: one K_P for all.
  const double kp = gains.K_P(0, 0);
  REQUIRE((gains.K_P.diagonal().array() - kp).abs().maxCoeff() <= 1e-12 * kp);
  const auto loop = controller::design::loop_stability(p.feedback_path, gains);
  REQUIRE(loop.poles.size() == 18);  // 12 suspension states, 6 integrators
  const double wd = s.omega_d_rad_s, wl = s.leak_rad_s, z = s.zeta;
  std::vector<std::complex<double>> roots;
  for (Eigen::Index j = 0; j < p.natural_frequencies_hz.size(); ++j) {
    const double wj2 = std::pow(kTwoPi * p.natural_frequencies_hz(j), 2);
    const std::array<double, 4> cubic{1 + kp, (1 + kp) * (wl + 2 * z * wd), wj2, wj2 * wl};
    for (const auto& r : test::polynomial_roots(cubic)) roots.push_back(r);
  }
  CHECK(test::match_poles(loop.poles, roots, 1, wd) <= 1e-8);
  CHECK(loop.stable());
}

TEST_CASE(
    "PI per strut: box8 (8 struts, 6 degrees of freedom) is accepted, its loops are stable and "
    "every mode is damped more than open loop",
    "[controller][pi][per_strut][box8]") {
  const auto p = scene::build_scene_plant(scene::load_scene(kBox8Scene));
  REQUIRE(p.model.nd() == 6);
  REQUIRE(p.struts.size() == 8);
  CHECK(p.gains.K_P.rows() == 8);
  CHECK(Eigen::MatrixXd(p.gains.K_P.diagonal().asDiagonal()) == p.gains.K_P);
  // A vertical strut at a corner r = (+-0.3, +-0.3, 0.05) from the centre of gravity pushes along
  // z: 1/m_V = 1/m + (r x z)^T I^-1 (r x z) = 1/40 + 0.3^2/1.0 + 0.3^2/1.2 = 0.19 per kg, by hand.
  const double wd = kTwoPi * p.scene.controller.omega_d_hz;
  const double k_p_vertical = 2.0e6 * 0.19 / (wd * wd) - 1;
  for (int i = 0; i < 4; ++i) {
    CHECK(std::abs(p.struts[static_cast<std::size_t>(i)].inverse_mass - 0.19) <= 1e-12);
    CHECK(std::abs(p.gains.K_P(i, i) - k_p_vertical) <= 1e-12 * k_p_vertical);
  }
  // The inclined struts in mirror pairs (I_xx != I_yy): T1 as T3, T2 as T4, unlike the vertical.
  CHECK(std::abs(p.gains.K_P(4, 4) - p.gains.K_P(6, 6)) <= 1e-12 * p.gains.K_P(4, 4));
  CHECK(std::abs(p.gains.K_P(5, 5) - p.gains.K_P(7, 7)) <= 1e-12 * p.gains.K_P(5, 5));
  CHECK(std::abs(p.gains.K_P(4, 4) - k_p_vertical) > 0.1 * k_p_vertical);
  CHECK(p.loop.stable());
  CHECK(scene::sampled_loop(p).stability.stable());
  // Open loop: the feedback path's 6 lightly damped modes; closed: every pole but the integrators.
  const auto open = damping_ratios(plant::lti::poles(p.feedback_path));
  const auto closed = damping_ratios(p.loop.poles);
  REQUIRE(open.size() == 12);
  REQUIRE(closed.size() == 14);  // 20 poles: 12 suspension + 8 integrator states, 6 at s = 0
  const double open_max = *std::max_element(open.begin(), open.end());
  const double closed_min = *std::min_element(closed.begin(), closed.end());
  INFO("open-loop damping at most " << open_max << ", closed-loop at least " << closed_min);
  CHECK(open_max < 0.01);
  CHECK(closed_min > 10 * open_max);
}

TEST_CASE(
    "PI per strut: an actuator without its collocated force sensor is refused at the scene's "
    "sensors entry",
    "[controller][pi][per_strut][box8]") {
  auto sc = scene::load_scene(kBox8Scene);
  sc.sensors[7] = "acc:z.M4";
  try {
    scene::build_scene_plant(sc);
    FAIL("accepted a PI scene whose actuator 8 has no collocated force sensor");
  } catch (const common::InputError& e) {
    const std::string what = e.what();
    INFO(what);
    // The entry's own line: the second line of the sensors list.
    CHECK(what.find("box8.toml:15:") != std::string::npos);
    CHECK(what.find("sensors entry 8 'acc:z.M4'") != std::string::npos);
    CHECK(what.find("'stress:e1.T4'") != std::string::npos);
  }
  auto drives_a_node = scene::load_scene(kBox8Scene);
  drives_a_node.actuators[0] = "force:z.P";
  drives_a_node.sensors[0] = "acc:z.P";
  CHECK_THROWS_WITH(scene::build_scene_plant(drives_a_node),
                    Catch::Contains("box8.toml:11:") && Catch::Contains("actuators entry 1"));
}
