// float against double over 10^6 steps (100 s at 10 kHz) of the metrology plant, dense and modal,
// within a bound derived from the rounding model (Higham, Accuracy and Stability of Numerical
// Algorithms, §3.1-3.5) and evaluated for this plant and this run.
//
// Both forms step  x_{k+1} = x_k + c_k,  c_k = Δ x_k + B u_k  with Δ = A - I (dense: Ad - I;
// modal: Λ - I, x the modal state). The output y_k = C x_k + D u_k takes C x_k from the step
// before, computed as (C A) x_{k-1} + (C B) u_{k-1} (plant/runtime/state_output.hpp). With
// u = 2^-24 (float), the float step rounds Δ, B, C A, C B and the input once each, forms c with
// at most NX + NU terms and adds it to x, so with γ_m = m u / (1 - m u), m = NX + 2 NU + 5,
//   x̂_{k+1} = A x̂_k + B u_k + δ_k,   |δ_k| <= u |x̂_k| + γ_m (|Δ| |x̂_k| + |B| |u_k|)
// (elementwise). The error e_k = x̂_k - x_k obeys e_{k+1} = A e_k + δ_k, e_0 = 0, so
//   |e_k| <= Σ_{i=0}^{k-1} |A^i| δ̄ =: M δ̄,   δ̄ = max over k of the bound on |δ_k|.
// The output's sums of NX + 2 NU terms with rounded C A, C B and D see the state error as
// C A e_{k-1} = C Σ_{i>=1} A^i δ_{k-1-i}, bounded by |C| M δ̄, so
//   |ŷ_k - y_k| <= |C| M δ̄ + γ_m max_k (|C| |A| |x̂_{k-1}| + |C| |B| |u_{k-1}| + |D| |u_k|).
// The double run's own error obeys the same bound with 2^-53 in place of 2^-24; it is covered by
// using u = 2^-24 + 2^-53. M is a property of the plant (a lightly damped mode makes its entries
// grow like 1 / (1 - |z|)); δ̄ uses the float run's own states. The bound is worst-case (every
// rounding in phase with the resonance), so the run stays far below it; the test reports how far.
#include <catch2/catch.hpp>

#include <random>
#include <type_traits>

#include "plant/lti/modal_form.hpp"
#include "plant/runtime/runtime_sizes.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using plant::runtime::DensePlant;
using plant::runtime::ModalPlant;

namespace {

constexpr int kSteps = 1000000;
constexpr int kNx = 12, kNu = 12, kNy = 12;

// Σ_{i=0}^{K-1} |A^i|, stopping once the terms no longer change the sum in double.
Eigen::MatrixXd abs_power_sum(const Eigen::MatrixXd& A, int K) {
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(A.rows(), A.cols());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(A.rows(), A.cols());
  for (int i = 0; i < K; ++i) {
    M += P.cwiseAbs();
    if (P.cwiseAbs().maxCoeff() < 1e-17 * M.maxCoeff()) break;
    P = A * P;
  }
  return M;
}

struct Comparison {
  Eigen::VectorXd error, bound, scale;  // per output, max over the run (scale: max |y|)
};

// Runs the double and float plants side by side on the same input and evaluates the bound.
template <template <typename, int, int, int> class Plant, typename Make>
Comparison compare(const Eigen::MatrixXd& Delta, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                   const Eigen::MatrixXd& D, Make make) {
  auto pd = make(std::type_identity<Plant<double, kNx, kNu, kNy>>{});
  auto pf = make(std::type_identity<Plant<float, kNx, kNu, kNy>>{});
  const double u_round = std::ldexp(1.0, -24) + std::ldexp(1.0, -53);
  const double m = kNx + 2 * kNu + 5;
  const double gamma = m * u_round / (1 - m * u_round);
  const Eigen::MatrixXd A = Delta + Eigen::MatrixXd::Identity(kNx, kNx);
  const Eigen::MatrixXd Ea = Delta.cwiseAbs(), Ba = B.cwiseAbs(), Ca = C.cwiseAbs(),
                        Da = D.cwiseAbs(), CAa = Ca * A.cwiseAbs(), CBa = Ca * Ba;

  // Floor accelerations ~1e-3 m/s² RMS (the scene's level) and actuator forces ~1 N RMS.
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, kNu, 1> u, u_prev = Eigen::Matrix<double, kNu, 1>::Zero();
  Eigen::VectorXd x_hat_prev = Eigen::VectorXd::Zero(kNx);
  Eigen::VectorXd delta_bar = Eigen::VectorXd::Zero(kNx), out_round = Eigen::VectorXd::Zero(kNy);
  Comparison c{Eigen::VectorXd::Zero(kNy), {}, Eigen::VectorXd::Zero(kNy)};
  for (int k = 0; k < kSteps; ++k) {
    for (int i = 0; i < kNu; ++i) u(i) = (i < 6 ? 1e-3 : 1.0) * n01(rng);
    const Eigen::Matrix<float, kNu, 1> uf = u.cast<float>();
    const Eigen::VectorXd x_hat = pf.state().template cast<double>();
    const Eigen::VectorXd y = pd.output(u);
    const Eigen::VectorXd y_hat = pf.output(uf).template cast<double>();
    c.error = c.error.cwiseMax((y_hat - y).cwiseAbs());
    c.scale = c.scale.cwiseMax(y.cwiseAbs());
    delta_bar = delta_bar.cwiseMax(u_round * x_hat.cwiseAbs() +
                                   gamma * (Ea * x_hat.cwiseAbs() + Ba * u.cwiseAbs()));
    out_round = out_round.cwiseMax(
        gamma * (CAa * x_hat_prev.cwiseAbs() + CBa * u_prev.cwiseAbs() + Da * u.cwiseAbs()));
    pd.advance(u);
    pf.advance(uf);
    x_hat_prev = x_hat;
    u_prev = u;
  }
  c.bound = Ca * (abs_power_sum(A, kSteps) * delta_bar) + out_round;
  return c;
}

void check(const Comparison& c) {
  const Eigen::ArrayXd error = c.error.array() / c.scale.array();
  const Eigen::ArrayXd bound = c.bound.array() / c.scale.array();
  INFO(std::scientific << "relative error " << error.maxCoeff() << ", bound " << bound.maxCoeff()
                       << ", error / bound <= " << (error / bound).maxCoeff());
  // Per output: error <= bound; the bound is not vacuous (a fraction of the signal); float really
  // ran in float.
  CHECK((error <= bound).all());
  CHECK(bound.maxCoeff() <= 0.1);
  CHECK(error.minCoeff() > 0);
}

}  // namespace

TEST_CASE("float vs double: dense metrology plant, 10^6 steps, within the derived bound",
          "[runtime][float][metrology]") {
  const auto& s = test::metrology().s.plant.sys;
  const Eigen::MatrixXd Delta = s.A - Eigen::MatrixXd::Identity(kNx, kNx);
  const auto c = compare<DensePlant>(Delta, s.B, s.C, s.D, [&](auto tag) {
    return decltype(tag)::type::from_matrices(s.A, s.B, s.C, s.D);
  });
  check(c);
}

TEST_CASE("float vs double: modal metrology plant, 10^6 steps, within the derived bound",
          "[runtime][float][metrology]") {
  const auto m = plant::lti::to_modal_form(test::metrology().s.plant);
  const auto c = compare<ModalPlant>(m.Lambda_minus_I, m.B, m.C, m.D, [&](auto tag) {
    return decltype(tag)::type::from_modal_form(m);
  });
  check(c);
}
