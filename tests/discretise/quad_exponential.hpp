// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Independent high-precision reference for ZOH and FOH (test_stiff_exponential.cpp): the FOH
// augmented matrix [A B 0; 0 0 I/T; 0 0 0]·T (discretise.hpp) exponentiated in binary128
// (__float128, 113-bit significand, unit round-off 9.6e-35) by a plain Taylor series with scaling
// and squaring, no balancing and no Padé: a different algorithm in a precision 2^60 finer than
// the code under test. A·T and B·T are exact here (53 + 53 bits fit in 113). ZOH's Ad, Bd are
// the Φ, Γ1 blocks of the same exponential. FOH's Bd, Dd are formed in binary128 too, then
// everything is rounded to double once.
//
// Checked against mpmath at 60 digits (tools/reference/discretise_reference.py): by
// test_stiff_exponential.cpp on a committed fixture (‖A T‖ = 9.5e7), and once by hand on a
// 5-mass chain with ‖A T‖ = 4e13, where the two agreed to double rounding (6e-17).
#include <Eigen/Dense>
#include <cmath>
#include <vector>
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace flexloop::test {

__extension__ typedef __float128 quad;

struct QuadMatrix {
  Eigen::Index n;
  std::vector<quad> v;  // row-major
  explicit QuadMatrix(Eigen::Index size) : n(size), v(static_cast<std::size_t>(size * size), 0) {}
  quad& operator()(Eigen::Index i, Eigen::Index j) {
    return v[static_cast<std::size_t>(i * n + j)];
  }
  quad operator()(Eigen::Index i, Eigen::Index j) const {
    return v[static_cast<std::size_t>(i * n + j)];
  }
};

inline QuadMatrix quad_product(const QuadMatrix& a, const QuadMatrix& b) {
  QuadMatrix c(a.n);
  for (Eigen::Index i = 0; i < a.n; ++i)
    for (Eigen::Index l = 0; l < a.n; ++l) {
      const quad ail = a(i, l);
      if (ail == 0) continue;
      for (Eigen::Index j = 0; j < a.n; ++j) c(i, j) += ail * b(l, j);
    }
  return c;
}

inline double quad_norm_1(const QuadMatrix& a) {
  double norm = 0;
  for (Eigen::Index j = 0; j < a.n; ++j) {
    double col = 0;
    for (Eigen::Index i = 0; i < a.n; ++i) col += std::abs(static_cast<double>(a(i, j)));
    norm = std::max(norm, col);
  }
  return norm;
}

// e^M: M / 2^s with ‖M / 2^s‖_1 <= 1/2, Taylor to 40 terms (truncation below 0.5^41/41! ~ 1e-62),
// then s squarings.
inline QuadMatrix quad_exponential(QuadMatrix m) {
#if defined(__AVX__)
  // The arithmetic below is libgcc's soft-float, encoded as legacy SSE. GCC inserts no vzeroupper
  // at -O1 (the sanitizer build; its pass needs -fexpensive-optimizations, which -O2 turns on),
  // so the native build's AVX code before this leaves the upper register halves dirty, and every
  // SSE instruction then pays a transition penalty: under the sanitizers this reference took 8x
  // as long (43.5 s against 5.3 s for the cantilever case).
  _mm256_zeroupper();
#endif
  int s = 0;
  for (double norm = quad_norm_1(m); norm > 0.5; norm /= 2) ++s;
  const quad scale = static_cast<quad>(std::ldexp(1.0, -s));  // exact power of two
  for (auto& x : m.v) x *= scale;
  QuadMatrix sum(m.n), term(m.n);
  for (Eigen::Index i = 0; i < m.n; ++i) sum(i, i) = term(i, i) = 1;
  for (int k = 1; k <= 40; ++k) {
    term = quad_product(term, m);
    for (auto& x : term.v) x /= k;
    for (std::size_t i = 0; i < sum.v.size(); ++i) sum.v[i] += term.v[i];
  }
  for (int i = 0; i < s; ++i) sum = quad_product(sum, sum);
  return sum;
}

struct ReferenceHolds {
  Eigen::MatrixXd zoh_A, zoh_B;         // Φ, Γ1
  Eigen::MatrixXd foh_A, foh_B, foh_D;  // Φ, Γ1 + (Φ - I) Γ2, D + C Γ2 (shifted state)
};

inline ReferenceHolds reference_holds(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                      const Eigen::MatrixXd& C, const Eigen::MatrixXd& D,
                                      double T) {
  const Eigen::Index n = A.rows(), m = B.cols(), ny = C.rows();
  QuadMatrix aug(n + 2 * m);
  const quad t = T;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) aug(i, j) = static_cast<quad>(A(i, j)) * t;
    for (Eigen::Index j = 0; j < m; ++j) aug(i, n + j) = static_cast<quad>(B(i, j)) * t;
  }
  for (Eigen::Index j = 0; j < m; ++j) aug(n + j, n + m + j) = 1;
  const QuadMatrix e = quad_exponential(aug);

  const auto phi = [&](Eigen::Index i, Eigen::Index j) { return e(i, j); };
  const auto g1 = [&](Eigen::Index i, Eigen::Index j) { return e(i, n + j); };
  const auto g2 = [&](Eigen::Index i, Eigen::Index j) { return e(i, n + m + j); };
  ReferenceHolds r{Eigen::MatrixXd(n, n), Eigen::MatrixXd(n, m), Eigen::MatrixXd(n, n),
                   Eigen::MatrixXd(n, m), Eigen::MatrixXd(ny, m)};
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) r.zoh_A(i, j) = r.foh_A(i, j) = double(phi(i, j));
    for (Eigen::Index j = 0; j < m; ++j) {
      r.zoh_B(i, j) = double(g1(i, j));
      quad b = g1(i, j) - g2(i, j);  // Γ1 + (Φ - I) Γ2
      for (Eigen::Index l = 0; l < n; ++l) b += phi(i, l) * g2(l, j);
      r.foh_B(i, j) = double(b);
    }
  }
  for (Eigen::Index i = 0; i < ny; ++i)
    for (Eigen::Index j = 0; j < m; ++j) {
      quad d = D(i, j);
      for (Eigen::Index l = 0; l < n; ++l) d += static_cast<quad>(C(i, l)) * g2(l, j);
      r.foh_D(i, j) = double(d);
    }
  return r;
}

}  // namespace flexloop::test
