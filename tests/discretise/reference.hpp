// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Independent references for the discretisation tests: a system built in real modal form with
// known eigenvalues, propagated mode by mode with closed-form (scalar, complex) solutions — no
// matrix exponential — and frequency responses by linear solves.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "plant/lti/state_space.hpp"

namespace flexloop::test {

using cd = std::complex<double>;
using plant::lti::StateSpace;

inline Eigen::MatrixXd random_matrix(std::mt19937& rng, Eigen::Index r, Eigen::Index c) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(r, c);
  for (Eigen::Index i = 0; i < r; ++i)
    for (Eigen::Index j = 0; j < c; ++j) m(i, j) = u(rng);
  return m;
}

/// prefix1, prefix2, ... prefixN. Appended, not "x" + std::to_string(k): GCC 12 warns falsely
/// (-Wrestrict, GCC bug 105329) on that prepend at -O3.
inline std::vector<std::string> numbered(const char* prefix, Eigen::Index n) {
  std::vector<std::string> names;
  for (Eigen::Index k = 1; k <= n; ++k)
    names.push_back(std::string(prefix).append(std::to_string(k)));
  return names;
}

/// A state space with the labels x1.., u1.., y1.. (every StateSpace needs labels).
inline StateSpace labelled(Eigen::MatrixXd A, Eigen::MatrixXd B, Eigen::MatrixXd C,
                           Eigen::MatrixXd D) {
  StateSpace s{std::move(A), std::move(B), std::move(C), std::move(D), {}, {}, {}};
  s.states = numbered("x", s.nx());
  s.inputs = numbered("u", s.nu());
  s.outputs = numbered("y", s.ny());
  return s;
}

// dx/dt = A x + B u with A = S J S^-1, B = S Bz, C = Cz S^-1, J real block diagonal:
// a 2x2 block [σ ω; -ω σ] per oscillatory mode, a 1x1 block σ per real mode.
struct ModalSystem {
  struct Mode {
    double sigma, omega;  // omega == 0: real 1x1 mode
  };
  std::vector<Mode> modes;
  Eigen::MatrixXd S, Bz, Cz, D;
  StateSpace ss;

  // The continuous eigenvalues σ ± jω.
  std::vector<cd> eigenvalues() const {
    std::vector<cd> out;
    for (const auto& m : modes) {
      out.emplace_back(m.sigma, m.omega);
      if (m.omega != 0) out.emplace_back(m.sigma, -m.omega);
    }
    return out;
  }

  // State in modal coordinates, one complex number per mode: c = p + jq for a block (p, q),
  // which obeys dc/dt = μ c + β u with μ = σ - jω and β = (row p of Bz) + j (row q of Bz).
  struct Modal {
    std::vector<cd> c;
  };

  Modal modal_from_z(const Eigen::VectorXd& z) const {
    Modal m;
    Eigen::Index k = 0;
    for (const auto& mode : modes) {
      if (mode.omega == 0) {
        m.c.emplace_back(z(k), 0.0);
        k += 1;
      } else {
        m.c.emplace_back(z(k), z(k + 1));
        k += 2;
      }
    }
    return m;
  }

  Eigen::VectorXd z_from_modal(const Modal& m) const {
    Eigen::VectorXd z(ss.nx());
    Eigen::Index k = 0;
    for (std::size_t i = 0; i < modes.size(); ++i) {
      z(k++) = m.c[i].real();
      if (modes[i].omega != 0) z(k++) = m.c[i].imag();
    }
    return z;
  }

  // Exact state after one step T with the input linear from u0 to u1 over the step:
  // c(T) = e^{μT} c0 + β (F1 u0 + G (u1 - u0)),  F1 = ∫0^T e^{μs} ds,
  // G = (1/T) ∫0^T e^{μs} (T - s) ds; series for small |μT| avoid cancellation.
  Modal step(const Modal& m0, const Eigen::VectorXd& u0, const Eigen::VectorXd& u1,
             double T) const {
    Modal m1;
    Eigen::Index k = 0;
    for (std::size_t i = 0; i < modes.size(); ++i) {
      const auto& mode = modes[i];
      const cd mu(mode.sigma, -mode.omega);
      cd beta_u0(Bz.row(k).dot(u0), 0.0), beta_du(Bz.row(k).dot(u1 - u0), 0.0);
      if (mode.omega != 0) {
        beta_u0 += cd(0.0, Bz.row(k + 1).dot(u0));
        beta_du += cd(0.0, Bz.row(k + 1).dot(u1 - u0));
      }
      const cd x = mu * T;
      cd f1, g;
      if (std::abs(x) < 1.0) {
        cd s1 = 0.0, s2 = 0.0;
        double fact1 = 1.0, fact2 = 2.0;  // (n+1)!, (n+2)!: sums of x^n/(n+1)!, x^n/(n+2)!
        cd xn = 1.0;
        for (int n = 0; n < 30; ++n) {
          s1 += xn / fact1;
          s2 += xn / fact2;
          xn *= x;
          fact1 *= (n + 2);
          fact2 *= (n + 3);
        }
        f1 = T * s1;
        g = T * s2;
      } else {
        f1 = (std::exp(x) - 1.0) / mu;
        g = (std::exp(x) - 1.0 - x) / (mu * x);
      }
      m1.c.push_back(std::exp(x) * m0.c[i] + f1 * beta_u0 + g * beta_du);
      k += mode.omega == 0 ? 1 : 2;
    }
    return m1;
  }

  Eigen::VectorXd output(const Modal& m, const Eigen::VectorXd& u) const {
    return Cz * z_from_modal(m) + D * u;
  }
};

// Lightly to well damped modes from 1.3 Hz to 140 Hz plus two real poles: 12 states.
inline ModalSystem make_modal_system(unsigned seed, Eigen::Index nu = 3, Eigen::Index ny = 2) {
  std::mt19937 rng(seed);
  ModalSystem m;
  const double two_pi = 2 * std::numbers::pi;
  const double f[] = {1.3, 7.0, 23.0, 61.0, 140.0};
  const double zeta[] = {0.02, 0.05, 0.1, 0.01, 0.3};
  for (int i = 0; i < 5; ++i) {
    const double wn = two_pi * f[i];
    m.modes.push_back({-zeta[i] * wn, wn * std::sqrt(1 - zeta[i] * zeta[i])});
  }
  m.modes.push_back({-3.0, 0.0});
  m.modes.push_back({-40.0, 0.0});
  const Eigen::Index n = 12;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
  Eigen::Index k = 0;
  for (const auto& mode : m.modes) {
    J(k, k) = mode.sigma;
    if (mode.omega != 0) {
      J(k, k + 1) = mode.omega;
      J(k + 1, k) = -mode.omega;
      J(k + 1, k + 1) = mode.sigma;
      k += 2;
    } else {
      k += 1;
    }
  }
  // Well-conditioned but far from orthogonal, so A is not normal.
  m.S = random_matrix(rng, n, n) + 3.0 * Eigen::MatrixXd::Identity(n, n);
  m.Bz = random_matrix(rng, n, nu);
  m.Cz = random_matrix(rng, ny, n);
  m.D = random_matrix(rng, ny, nu);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(m.S);
  const Eigen::MatrixXd Sinv = lu.inverse();
  m.ss = labelled(m.S * J * Sinv, m.S * m.Bz, m.Cz * Sinv, m.D);
  return m;
}

// H(s) = C (sI - A)^-1 B + D by a linear solve.
inline Eigen::MatrixXcd frequency_response(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                           const Eigen::MatrixXd& C, const Eigen::MatrixXd& D,
                                           cd s) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXcd M = s * Eigen::MatrixXcd::Identity(n, n) - A.cast<cd>();
  const Eigen::MatrixXcd X = M.partialPivLu().solve(B.cast<cd>());
  return C.cast<cd>() * X + D.cast<cd>();
}

// y_k = Cd ξ_k + Dd u_k,  ξ_{k+1} = Ad ξ_k + Bd u_k, for k = 0 .. u.size()-1.
inline std::vector<Eigen::VectorXd> simulate(const StateSpace& d, Eigen::VectorXd xi,
                                             const std::vector<Eigen::VectorXd>& u) {
  std::vector<Eigen::VectorXd> y;
  for (const auto& uk : u) {
    y.push_back(d.C * xi + d.D * uk);
    xi = d.A * xi + d.B * uk;
  }
  return y;
}

// max_k |a_k - b_k| / max_k |b_k| over all channels: relative to the response's size, so that
// samples where the reference crosses zero do not dominate.
inline double relative_error(const std::vector<Eigen::VectorXd>& a,
                             const std::vector<Eigen::VectorXd>& b) {
  double err = 0, scale = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    err = std::max(err, (a[k] - b[k]).cwiseAbs().maxCoeff());
    scale = std::max(scale, b[k].cwiseAbs().maxCoeff());
  }
  return err / scale;
}

inline double relative_difference(const Eigen::MatrixXcd& a, const Eigen::MatrixXcd& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace flexloop::test
