// SPDX-License-Identifier: BSD-3-Clause
// The fixed-size discrete PI force-feedback controller (controller/runtime/pi_controller.hpp):
// the law against an independent dynamic-size state-space reference, start-up checks, bumpless
// start, anti-windup, and the loop around the metrology frame against the offline model of the
// sampled closed loop (plant/lti/feedback_interconnection.hpp).
#include <catch2/catch.hpp>

#include <random>

#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "tests/discretise/reference.hpp"
#include "tests/support/closed_loop.hpp"
#include "tests/support/discrete_systems.hpp"
#include "tests/support/dynamic_reference.hpp"
#include "tests/support/metrology.hpp"
#include "tests/support/pi_reference.hpp"

using namespace flexloop;
using artefact::PiParameters;
using controller::runtime::PiController;
using Pi6 = PiController<double, 6>;
using Vec6 = Pi6::Vector;

namespace {

// Coupled gains with I + K_P and K_I well invertible.
PiParameters random_parameters(unsigned seed, double leak_rad_s) {
  std::mt19937 rng(seed);
  PiParameters p;
  p.K_P = 5.0 * Eigen::MatrixXd::Identity(6, 6) + test::random_matrix(rng, 6, 6);
  p.K_I = 200.0 * (Eigen::MatrixXd::Identity(6, 6) + 0.2 * test::random_matrix(rng, 6, 6));
  p.dt = 1e-4;
  p.leak_rad_s = leak_rad_s;
  return p;
}

struct LawComparison {
  double disagreement;  // max_k |u_k - u_ref,k| / max_k |u_ref,k|
  double saturated;     // fraction of samples with a channel at its limit
};

// Both controllers on the same seeded N(0, 1) measurements.
LawComparison compare_law(const PiParameters& p, int steps) {
  auto pi = Pi6::from_parameters(p);
  auto ref = test::pi_reference(p);
  std::mt19937 rng(9);
  std::normal_distribution<double> n01;
  double diff = 0, scale = 0;
  int saturated = 0;
  for (int k = 0; k < steps; ++k) {
    Vec6 y;
    for (int i = 0; i < 6; ++i) y(i) = n01(rng);
    const Vec6 u = pi.step(y);
    const Eigen::VectorXd u_ref = ref.step(y);
    diff = std::max(diff, (u - u_ref).cwiseAbs().maxCoeff());
    scale = std::max(scale, u_ref.cwiseAbs().maxCoeff());
    saturated += (u_ref.array() == ref.u_max.array() || u_ref.array() == ref.u_min.array()).any();
  }
  return {diff / scale, static_cast<double>(saturated) / steps};
}

}  // namespace

TEST_CASE("PI runtime: the law equals the state-space reference (loop solved per sample)",
          "[controller][pi]") {
  for (double leak : {0.0, 2 * 3.141592653589793 * 0.5}) {
    CAPTURE(leak);
    auto p = random_parameters(1, leak);
    const auto plain = compare_law(p, 2000);
    CHECK(plain.disagreement <= 1e-12);
    CHECK(plain.saturated == 0);
    // A general sensor feedthrough D22.
    std::mt19937 rng(4);
    p.feedthrough = Eigen::MatrixXd::Identity(6, 6) + 0.1 * test::random_matrix(rng, 6, 6);
    CHECK(compare_law(p, 2000).disagreement <= 1e-12);
    // Limits that clamp a good share of the samples: the anti-windup path against the
    // reference's own formulation (Cc x' = (I - Dc D22) u - Dc f).
    p.u_min = Eigen::VectorXd::Constant(1, -0.8);
    p.u_max = Eigen::VectorXd::Constant(1, 0.8);
    const auto clamped = compare_law(p, 2000);
    CHECK(clamped.disagreement <= 1e-12);
    CHECK(clamped.saturated >= 0.2);
  }
}

TEST_CASE("PI runtime: start-up checks name what is wrong", "[controller][pi]") {
  auto p = random_parameters(2, 0);
  CHECK_NOTHROW(Pi6::from_parameters(p));
  auto bad = p;
  bad.K_P = Eigen::MatrixXd::Identity(5, 5);
  CHECK_THROWS_WITH(Pi6::from_parameters(bad), Catch::Contains("K_P is 5x5, expected 6x6"));
  bad = p;
  bad.K_P = -Eigen::MatrixXd::Identity(6, 6);
  CHECK_THROWS_WITH(Pi6::from_parameters(bad), Catch::Contains("I + K_P D22 is singular"));
  bad = p;
  bad.K_I.row(2).setZero();
  CHECK_THROWS_WITH(Pi6::from_parameters(bad), Catch::Contains("K_I is singular"));
  bad = p;
  bad.dt = 0;
  CHECK_THROWS_WITH(Pi6::from_parameters(bad), Catch::Contains("dt must be"));
  bad = p;
  bad.u_min = Eigen::VectorXd::Constant(3, -1);
  CHECK_THROWS_WITH(Pi6::from_parameters(bad), Catch::Contains("u_min has 3 values"));
  bad = p;
  bad.u_min = Eigen::VectorXd::Constant(1, 1);
  bad.u_max = Eigen::VectorXd::Constant(1, -1);
  CHECK_THROWS_WITH(Pi6::from_parameters(bad), Catch::Contains("u_min must be <= u_max"));
}

TEST_CASE("PI runtime: bumpless start, the first command equals the command in force",
          "[controller][pi]") {
  for (const auto& p : {random_parameters(3, 0), test::metrology_pi_parameters()}) {
    auto pi = Pi6::from_parameters(p);
    const Vec6 y_now = (Vec6() << 1.5, -2, 0.3, 4, -0.7, 2.2).finished();
    const Vec6 u_now = (Vec6() << 0.2, 0.1, -0.4, 0.05, 0.3, -0.25).finished();
    pi.start(y_now, u_now);
    CHECK(pi.previous_command() == u_now);
    const Vec6 u = pi.step(y_now);
    CHECK((u - u_now).cwiseAbs().maxCoeff() <= 1e-12 * u_now.cwiseAbs().maxCoeff());
  }
  // After reset the controller is at rest: zero measurement, zero command.
  auto pi = Pi6::from_parameters(random_parameters(3, 0));
  pi.step(Vec6::Ones());
  pi.reset();
  CHECK(pi.step(Vec6::Zero()).isZero(0));
}

TEST_CASE("PI runtime: anti-windup, after a long saturation the force recovers without overshoot",
          "[controller][pi][windup]") {
  // The force loop on a rigid structure: the sensors measure an external force plus the held
  // command, y_k = f_k + u_{k-1}; the controller drives the total force e = f + u to zero
  // (u -> -f). With the metrology gains (coupled K_P) and limits ±L, f = 3 L s (unreachable) for
  // 2 s, then f = 0.5 L s (reachable), s a sign pattern. Without anti-windup the integrator winds
  // up over the 2 s and, after the release, holds the command at the limit: e overshoots zero by
  // 0.5 L for a long time. With it, e stays on its side of zero and decays.
  constexpr double L = 1.0;
  constexpr int kSaturate = 20000, kRecover = 20000;
  auto p = test::metrology_pi_parameters();
  p.u_min = Eigen::VectorXd::Constant(1, -L);
  p.u_max = Eigen::VectorXd::Constant(1, L);
  const Vec6 s = (Vec6() << 1, -1, 1, 1, -1, -1).finished();

  struct Recovery {
    double overshoot = 0;  // max over k >= release, i of -s_i e_k,i: e past zero, against f
    int settle = -1;       // samples after release until |e| < 1e-3 L for good
  };
  const auto run = [&](auto&& controller) {
    Vec6 u_prev = Vec6::Zero();
    Recovery r;
    for (int k = 0; k < kSaturate + kRecover; ++k) {
      const Vec6 f = (k < kSaturate ? 3.0 : 0.5) * L * s;
      const Vec6 y = f + u_prev;
      const Vec6 u = controller(y);
      u_prev = u;
      const Vec6 e = f + u;
      if (k < kSaturate) continue;
      r.overshoot = std::max(r.overshoot, (-s.array() * e.array()).maxCoeff());
      if (e.cwiseAbs().maxCoeff() >= 1e-3 * L) r.settle = k - kSaturate + 1;
    }
    return r;
  };

  auto pi = Pi6::from_parameters(p);
  const auto with = run([&](const Vec6& y) { return pi.step(y); });
  auto windup = test::pi_reference(p);
  windup.anti_windup = false;
  const auto without = run([&](const Vec6& y) { return Vec6(windup.step(y)); });
  CAPTURE(with.overshoot, with.settle, without.overshoot, without.settle);
  CHECK(with.overshoot <= 1e-9 * L);
  CHECK(with.settle <= 2000);  // 0.2 s
  CHECK(without.overshoot >= 0.4 * L);
  CHECK(without.settle > 10 * with.settle);
}

TEST_CASE(
    "PI runtime: around the metrology frame the loop matches the offline sampled closed "
    "loop step by step, and the uncompensated law diverges",
    "[controller][pi][metrology]") {
  const auto& m = test::metrology();
  const auto& pd = m.s.plant.sys;
  using Plant = plant::runtime::DensePlant<double, 12, 12, 12, 6>;  // holds the command
  test::ClosedLoop<Plant, Pi6, 6> loop(Plant::from_matrices(pd.A, pd.B, pd.C, pd.D),
                                       Pi6::from_parameters(test::metrology_pi_parameters()));
  const auto& cl = m.s.closed_loop.sys;
  test::PlantReference model{cl.A, cl.B, cl.C, cl.D};
  // K_P has eigenvalues up to ~23 (why the feedthrough must be compensated); the closed loop's
  // poles are inside the unit circle apart from the integrators at z = 1. Its matrix is badly
  // scaled (||A|| ~ 1e7), so eig(A) is only good to eps ||A||; the modal form's balanced
  // eigenvalues of A - I are accurate near z = 1.
  const Eigen::VectorXcd kp_eig = m.p.gains.K_P.eigenvalues();
  CHECK(kp_eig.cwiseAbs().maxCoeff() > 20);
  const auto modes = plant::lti::to_modal_form(m.s.closed_loop);
  const Eigen::VectorXcd poles = modes.Lambda.eigenvalues();
  INFO(std::scientific << "spectral radius: eig(A) " << m.s.closed_loop.spectral_radius
                       << ", balanced modal form " << poles.cwiseAbs().maxCoeff());
  CHECK(poles.cwiseAbs().maxCoeff() <= 1 + 1e-12);

  constexpr int kSteps = 100000;  // 10 s at 10 kHz
  std::mt19937 rng(21);
  std::normal_distribution<double> n01;
  double diff = 0, scale = 0, early = 0, late = 0;
  for (int k = 0; k < kSteps; ++k) {
    Vec6 w;
    for (int i = 0; i < 6; ++i) w(i) = 1e-3 * n01(rng);
    const Vec6 z = loop.step(w).head<6>();
    const Eigen::VectorXd z_model = model.output(w);
    model.advance(w);
    diff = std::max(diff, (z - z_model).cwiseAbs().maxCoeff());
    scale = std::max(scale, z_model.cwiseAbs().maxCoeff());
    (k < kSteps / 2 ? early : late) += z.squaredNorm();
  }
  INFO(std::scientific << "relative difference " << diff / scale << ", RMS ratio late/early "
                       << std::sqrt(late / early));
  CHECK(diff <= 1e-12 * scale);
  // Bounded: the second 5 s carry no more energy than the first (stationary response).
  CHECK(late <= 1.5 * early);

  // The plain sampled law u_k = -(K_P y_k + K_I xi_k) on the raw measurement feeds its own
  // command back through D22 = I with one sample of delay: u_k ≈ -K_P u_{k-1}.
  auto naive_plant = Plant::from_matrices(pd.A, pd.B, pd.C, pd.D);
  Eigen::Matrix<double, 12, 1> in = Eigen::Matrix<double, 12, 1>::Zero();
  Vec6 xi = Vec6::Zero();
  const Eigen::MatrixXd K_P = m.p.gains.K_P, K_I = m.p.gains.K_I;
  int diverged_at = -1;
  for (int k = 0; k < 1000 && diverged_at < 0; ++k) {
    for (int i = 0; i < 6; ++i) in(i) = 1e-3 * n01(rng);
    const auto y = naive_plant.output(in.head<6>());
    const Vec6 sigma = y.tail<6>();
    in.tail<6>() = -(K_P * sigma + K_I * xi);
    xi += m.s.plant.dt * sigma;
    naive_plant.advance(in);
    if (!(y.head<6>().cwiseAbs().maxCoeff() <= 1e6 * scale)) diverged_at = k;
  }
  CAPTURE(diverged_at);
  CHECK(diverged_at >= 0);
}
