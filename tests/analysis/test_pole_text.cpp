// SPDX-License-Identifier: BSD-3-Clause
// Poles as printed (plant/lti/pole_text.hpp): a pole within round-off of s = 0 is an integrator,
// printed as 0 rad/s without a damping; every other pole keeps its frequency and damping. On
// systems whose poles are known exactly (a rotated block diagonal) and on the metrology frame's
// PI loop (six integrators by design, doc/design.md §4).
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <random>
#include <string>

#include "numeric/constants.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/pole_text.hpp"

using namespace flexloop;
using plant::lti::damping_ratio;
using plant::lti::integrator_tolerance;
using plant::lti::is_integrator;
using plant::lti::pole_text;
using plant::lti::StateSpace;

namespace {

// A = Q blockdiag(0 x zeros, [s, w; -w, s] per pair, r per real pole) Q^T, Q a random orthogonal
// matrix: the eigenvalues are known exactly, and the computed zeros are not exact zeros.
StateSpace rotated_system(int zeros, const std::vector<std::complex<double>>& pairs,
                          const std::vector<double>& reals, unsigned seed) {
  const int n = zeros + 2 * static_cast<int>(pairs.size()) + static_cast<int>(reals.size());
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  int k = zeros;
  for (const auto& p : pairs) {
    D(k, k) = D(k + 1, k + 1) = p.real();
    D(k, k + 1) = p.imag();
    D(k + 1, k) = -p.imag();
    k += 2;
  }
  for (const double r : reals) D(k, k) = r, ++k;
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd R(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) R(i, j) = g(rng);
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(R).householderQ();
  StateSpace s;
  s.A = Q * D * Q.transpose();
  s.B = Eigen::MatrixXd::Ones(n, 1);
  s.C = Eigen::MatrixXd::Ones(1, n);
  s.D = Eigen::MatrixXd::Zero(1, 1);
  for (int i = 0; i < n; ++i) s.states.push_back("x" + std::to_string(i));
  s.inputs = {"u"};
  s.outputs = {"y"};
  return s;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("a pole within round-off of s = 0 prints as an integrator, without a damping",
          "[analysis][poles]") {
  // The line: +9.6e-14 rad/s beside poles up to 62.8 rad/s printed "damping -1.0000".
  const Eigen::VectorXcd loop =
      (Eigen::VectorXcd(3) << std::complex<double>(9.6e-14, 0), std::complex<double>(-31.5, -54.4),
       std::complex<double>(-31.5, 54.4))
          .finished();
  const double tol = integrator_tolerance(loop);
  CHECK(tol == Approx(plant::lti::kIntegratorRoundOff * std::abs(loop(1))));
  CHECK(is_integrator(loop(0), tol));
  CHECK(std::isnan(damping_ratio(loop(0), tol)));
  const std::string text = pole_text(loop(0), tol);
  CHECK(text == "0 rad/s, integrator (computed |s| = 9.6e-14 rad/s, round-off)");
  CHECK_FALSE(contains(text, "damping"));
  CHECK_FALSE(contains(text, "9.6e-14 rad/s ("));
  // The pair keeps its frequency and damping: 62.862 rad/s = 10.0048 Hz, 31.5 / 62.862 = 0.5011.
  CHECK_FALSE(is_integrator(loop(2), tol));
  CHECK(damping_ratio(loop(2), tol) == Approx(31.5 / std::abs(loop(2))));
  CHECK(pole_text(loop(2), tol) == "-31.5 + 54.4j rad/s (10.0048 Hz, damping 0.5011)");
  // Exactly zero (a system of integrators only, e.g. its tolerance is 0): still an integrator.
  CHECK(is_integrator(0.0, 0.0));
  CHECK(pole_text(0.0, 0.0) == "0 rad/s, integrator");
}

TEST_CASE("computed poles: the zeros of a rotated system are integrators, a slow real pole is not",
          "[analysis][poles]") {
  // Three integrators, a 3.2 Hz pair (damping 0.05), a 300 rad/s pair and a real pole 1e-9 times
  // the spectral radius: slow, but a pole with a time constant, not round-off.
  const double radius = 300;
  const auto s = rotated_system(3, {{-1, 19.975}, {-30, std::sqrt(radius * radius - 900)}},
                                {-1e-9 * radius}, 7);
  const Eigen::VectorXcd p = plant::lti::poles(s);
  const double tol = integrator_tolerance(p);
  CHECK(tol == Approx(plant::lti::kIntegratorRoundOff * radius).epsilon(1e-9));
  int integrators = 0;
  double largest_zero = 0;
  for (const auto& z : p) {
    const std::string text = pole_text(z, tol);
    INFO(z << ": " << text);
    if (is_integrator(z, tol)) {
      ++integrators;
      largest_zero = std::max(largest_zero, std::abs(z));
      CHECK_FALSE(contains(text, "damping"));
    } else {
      CHECK(contains(text, "damping"));
      CHECK(damping_ratio(z, tol) > 0);  // every pole of this system is stable
    }
  }
  CHECK(integrators == 3);
  // The computed zeros sit far inside the tolerance (a few eps x the radius).
  INFO("largest computed zero " << largest_zero << " = " << largest_zero / (numeric::kEps * radius)
                                << " eps x radius");
  CHECK(largest_zero <= tol / 8);
}

TEST_CASE("the metrology frame's PI loop has six integrators, printed as such, the rest damped 0.5",
          "[analysis][poles]") {
  const auto p = scene::build_scene_plant(scene::load_scene("tools/scenes/metrology_frame.toml"));
  const Eigen::VectorXcd& poles = p.loop.poles;
  REQUIRE(poles.size() == 18);
  const double tol = integrator_tolerance(poles);
  int integrators = 0;
  double largest_zero = 0;
  for (const auto& s : poles) {
    INFO(s << ": " << pole_text(s, tol));
    if (is_integrator(s, tol)) {
      ++integrators;
      largest_zero = std::max(largest_zero, std::abs(s));
    } else {
      // The closed-loop pairs at omega_d = 10 Hz, zeta = 0.5 (slightly more: the struts' own
      // damping).
      CHECK(std::abs(s) / numeric::kTwoPi == Approx(10).epsilon(1e-3));
      CHECK(damping_ratio(s, tol) == Approx(0.5).epsilon(0.01));
    }
  }
  CHECK(integrators == 6);
  const double radius = poles.cwiseAbs().maxCoeff();
  INFO("largest computed integrator |s| = " << largest_zero << " rad/s = "
                                            << largest_zero / (numeric::kEps * radius)
                                            << " eps x spectral radius " << radius);
  CHECK(largest_zero <= tol / 8);
}
