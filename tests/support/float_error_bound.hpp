// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// float against double, side by side on the same input, with the error bound derived from the
// rounding model (Higham, Accuracy and Stability of Numerical Algorithms, §3.1-3.5) and evaluated
// for this plant and this run.
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
//
// Used by tests/runtime/test_float_double.cpp (10^6 steps) and tests/hard_cases (10^8 steps).
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <cmath>
#include <type_traits>

#include "numeric/column_product.hpp"

namespace flexloop::test {

// Σ_{i=0}^{K-1} |A^i|, stopping once the terms no longer change the sum in double.
inline Eigen::MatrixXd abs_power_sum(const Eigen::MatrixXd& A, long K) {
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(A.rows(), A.cols());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(A.rows(), A.cols());
  for (long i = 0; i < K; ++i) {
    M += P.cwiseAbs();
    if (P.cwiseAbs().maxCoeff() < 1e-17 * M.maxCoeff()) break;
    P = A * P;
  }
  return M;
}

struct FloatComparison {
  Eigen::VectorXd error, bound, scale;  // per output, max over the run (scale: max |y|)
};

/// Runs the double and float plants (make(std::type_identity<Plant<Scalar, NX, NU, NY>>{}))
/// side by side for `steps` steps on the input that input(k, u) writes into u, and evaluates the
/// bound. The rounding terms use each step's own |x̂|, |u| (fixed-size, no allocation per step).
// Plant's parameter list ends in a pack: it then matches plants with further defaulted parameters
// (DensePlant's and ModalPlant's NH) without C++17's relaxed matching, which clang 14 leaves off.
template <template <typename, int, int, int, int...> class Plant, int NX, int NU, int NY,
          typename Make, typename Input>
FloatComparison compare_float_double(const Eigen::MatrixXd& Delta, const Eigen::MatrixXd& B,
                                     const Eigen::MatrixXd& C, const Eigen::MatrixXd& D, long steps,
                                     Make make, Input input) {
  using Vx = Eigen::Matrix<double, NX, 1>;
  using Vu = Eigen::Matrix<double, NU, 1>;
  using Vy = Eigen::Matrix<double, NY, 1>;
  auto pd = make(std::type_identity<Plant<double, NX, NU, NY>>{});
  auto pf = make(std::type_identity<Plant<float, NX, NU, NY>>{});
  const double u_round = std::ldexp(1.0, -24) + std::ldexp(1.0, -53);
  const double m = NX + 2 * NU + 5;
  const double gamma = m * u_round / (1 - m * u_round);
  const Eigen::MatrixXd A = Delta + Eigen::MatrixXd::Identity(NX, NX);
  const Eigen::Matrix<double, NX, NX> Ea = Delta.cwiseAbs();
  const Eigen::Matrix<double, NX, NU> Ba = B.cwiseAbs();
  const Eigen::Matrix<double, NY, NX> Ca = C.cwiseAbs(), CAa = C.cwiseAbs() * A.cwiseAbs();
  const Eigen::Matrix<double, NY, NU> Da = D.cwiseAbs(), CBa = C.cwiseAbs() * B.cwiseAbs();

  // The products of the bound are the step's own fixed-size kernels (numeric/column_product.hpp):
  // Eigen's product of a fixed-size matrix with an expression goes through its general
  // matrix-vector routine, a third of a 10^8-step run's time.
  Vu u, abs_u, abs_u_prev = Vu::Zero();
  Vx abs_x_hat_prev = Vx::Zero(), delta_bar = Vx::Zero();
  Vy error = Vy::Zero(), scale = Vy::Zero(), out_round = Vy::Zero();
  for (long k = 0; k < steps; ++k) {
    input(k, u);
    const Eigen::Matrix<float, NU, 1> uf = u.template cast<float>();
    const Vx abs_x_hat = pf.state().template cast<double>().cwiseAbs();
    abs_u = u.cwiseAbs();
    const Vy y = pd.output(u);
    const Vy y_hat = pf.output(uf).template cast<double>();
    error = error.cwiseMax((y_hat - y).cwiseAbs());
    scale = scale.cwiseMax(y.cwiseAbs());
    delta_bar = delta_bar.cwiseMax(u_round * abs_x_hat +
                                   gamma * numeric::product_sum(Ea, abs_x_hat, Ba, abs_u));
    out_round =
        out_round.cwiseMax(gamma * (numeric::product_sum(CAa, abs_x_hat_prev, CBa, abs_u_prev) +
                                    numeric::column_product(Da, abs_u)));
    pd.advance(u);
    pf.advance(uf);
    abs_x_hat_prev = abs_x_hat;
    abs_u_prev = abs_u;
  }
  return {error, Ca * (abs_power_sum(A, steps) * delta_bar) + out_round, scale};
}

/// Per output: error <= bound; the bound is not vacuous (a fraction of the signal); float really
/// ran in float.
inline void check_float_comparison(const FloatComparison& c) {
  const Eigen::ArrayXd error = c.error.array() / c.scale.array();
  const Eigen::ArrayXd bound = c.bound.array() / c.scale.array();
  WARN(std::scientific << "float vs double: relative error " << error.maxCoeff() << ", bound "
                       << bound.maxCoeff() << ", error / bound <= " << (error / bound).maxCoeff());
  CHECK((error <= bound).all());
  CHECK(bound.maxCoeff() <= 0.1);
  CHECK(error.minCoeff() > 0);
}

}  // namespace flexloop::test
