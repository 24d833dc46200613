// SPDX-License-Identifier: BSD-3-Clause
// The general (start-up-sized) PI controller: against the independent dynamic-size state-space
// reference (tests/support/dynamic_reference.hpp, with the loop solved by an LU every sample) at
// channel counts the runtime has no compiled path for, with saturation, a coupled feedthrough and
// a leak; and against the compiled PiController on the metrology frame's gains.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"
#include "tests/support/dynamic_reference.hpp"
#include "tests/support/metrology.hpp"
#include "tests/support/pi_reference.hpp"

using namespace flexloop;
using artefact::PiParameters;
using controller::runtime::GeneralPiController;

namespace {

PiParameters coupled_parameters(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  // Couplings scaled by 1/sqrt(n), so the spread of the gains' eigenvalues does not grow with n.
  const double c = 1.0 / std::sqrt(static_cast<double>(n));
  PiParameters p;
  p.K_P = 5.0 * I + c * test::random_matrix(rng, n, n);
  p.K_I = 200.0 * (I + 0.2 * c * test::random_matrix(rng, n, n));
  p.feedthrough = I + 0.1 * c * test::random_matrix(rng, n, n);
  p.dt = 1e-4;
  p.leak_rad_s = 3.0;
  p.u_min = Eigen::VectorXd::Constant(1, -1.5);
  p.u_max = Eigen::VectorXd::Constant(1, 1.5);
  return p;
}

}  // namespace

TEST_CASE("general PI: any channel count matches the state-space reference, saturating",
          "[controller][general]") {
  // Sample by sample: before each step the reference takes the controller's integrator state
  // and last command, so each step's law (saturation and anti-windup included) is compared on
  // its own. Run freely, a loop that saturates this often is sensitive to the last bit (two
  // correct implementations part after a few hundred samples), so free runs compare nothing.
  for (const Eigen::Index n :
       {Eigen::Index{1}, Eigen::Index{3}, Eigen::Index{9}, Eigen::Index{64}}) {
    CAPTURE(n);
    const PiParameters p = coupled_parameters(n, static_cast<unsigned>(n));
    auto pi = GeneralPiController<double>::from_parameters(p, n);
    auto ref = test::pi_reference(p);
    std::mt19937 rng(7);
    std::normal_distribution<double> n01;
    double u_err = 0, x_err = 0;
    int saturated = 0;
    for (int k = 0; k < 4000; ++k) {
      Eigen::VectorXd y(n);
      for (auto& v : y) v = 0.5 * n01(rng) + 0.25 * std::sin(1e-3 * k);
      ref.x = pi.state();
      ref.u_prev = pi.previous_command();
      const Eigen::VectorXd u_ref = ref.step(y);
      const Eigen::VectorXd u = pi.step(y);
      u_err = std::max(u_err, (u - u_ref).cwiseAbs().maxCoeff());
      const Eigen::VectorXd x = pi.state();
      x_err =
          std::max(x_err, (x - ref.x).cwiseAbs().maxCoeff() / (1 + ref.x.cwiseAbs().maxCoeff()));
      saturated += (u_ref.cwiseAbs().array() >= 1.5).any() ? 1 : 0;
    }
    CHECK(saturated > 100);  // the anti-windup path ran
    CHECK(u_err < 1e-9);     // of commands up to 1.5: the reference solves the loop each sample
    CHECK(x_err < 1e-9);
  }
}

TEST_CASE("general PI: the metrology frame's gains give the compiled controller's commands",
          "[controller][general]") {
  // Unsaturated: under white noise the metrology gains (K_P eigenvalues up to 23) with limits
  // that clamp most samples make the loop sensitive to the last bit (the compiled controller
  // against itself, one input changed by 1e-15, differs by 1e-9 after 400 samples and by the
  // whole range after 1000). The anti-windup is compared against the reference above, with gains
  // under which it contracts.
  auto params = test::metrology_pi_parameters();
  params.feedthrough_delay = 2;
  auto fixed = controller::runtime::PiController<double, 6>::from_parameters(params);
  auto general = GeneralPiController<double>::from_parameters(params, 6);
  std::mt19937 rng(9);
  std::normal_distribution<double> n01;
  double err = 0;
  for (int k = 0; k < 20000; ++k) {
    Eigen::Matrix<double, 6, 1> y;
    for (auto& v : y) v = 0.5 * n01(rng);
    const Eigen::Matrix<double, 6, 1> u = fixed.step(y);
    err = std::max(err, (general.step(y) - u).cwiseAbs().maxCoeff());
  }
  CHECK(err < 1e-12);
  CHECK((general.state() - fixed.state()).cwiseAbs().maxCoeff() <
        1e-9 * (1 + fixed.state().cwiseAbs().maxCoeff()));
}

TEST_CASE("general PI: start-up refuses what the compiled controller refuses",
          "[controller][general]") {
  PiParameters p = coupled_parameters(4, 1);
  CHECK_THROWS_WITH(GeneralPiController<double>::from_parameters(p, 5),
                    Catch::Contains("K_P is 4x4, expected 5x5"));
  CHECK_THROWS_WITH(GeneralPiController<double>::from_parameters(p, 0),
                    Catch::Contains("0 channels; it takes 1 .. 64"));
  p.K_I.setZero();
  CHECK_THROWS_WITH(GeneralPiController<double>::from_parameters(p, 4),
                    Catch::Contains("K_I is singular"));
}
