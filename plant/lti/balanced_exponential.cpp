// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/balanced_exponential.hpp"

#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flexloop::plant::lti {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;

// |exponent| per index: the entries move by at most 2^256, so only data below ~1e-230 could
// underflow and lose bits; the ratios a stiff plant needs are a few dozen powers of two.
constexpr int kMaxExponent = 128;
constexpr int kMaxSweeps = 100;  // each kept step shrinks the off-diagonal sum by 5 %: never hit
constexpr double kShrink = 0.95;

double off_diagonal_column_sum(const MatrixXd& m, Index i) {
  const auto col = m.col(i).cwiseAbs();
  return col.head(i).sum() + col.tail(m.rows() - i - 1).sum();
}

double off_diagonal_row_sum(const MatrixXd& m, Index i) {
  const auto row = m.row(i).cwiseAbs();
  return row.head(i).sum() + row.tail(m.cols() - i - 1).sum();
}

// Column i times 2^k, row i times 2^-k: exact, and the diagonal entry comes back unchanged.
void scale_index(Balancing& b, Index i, int k) {
  b.balanced.col(i) *= std::ldexp(1.0, k);
  b.balanced.row(i) *= std::ldexp(1.0, -k);
  b.exponents(i) += k;
}

int clamp_step(const Balancing& b, Index i, int k) {
  return std::clamp(b.exponents(i) + k, -kMaxExponent, kMaxExponent) - b.exponents(i);
}

// One Parlett-Reinsch sweep; true when some index was rescaled.
bool sweep(Balancing& b) {
  bool changed = false;
  for (Index i = 0; i < b.balanced.rows(); ++i) {
    const double c = off_diagonal_column_sum(b.balanced, i);
    const double r = off_diagonal_row_sum(b.balanced, i);
    if (c == 0 || r == 0) continue;  // nothing to balance against
    // c 2^k = r 2^-k  <=>  k = log2(r / c) / 2, to the nearest integer.
    const int k =
        clamp_step(b, i, static_cast<int>(std::lround(0.5 * (std::log2(r) - std::log2(c)))));
    if (k == 0 || std::ldexp(c, k) + std::ldexp(r, -k) >= kShrink * (c + r)) continue;
    scale_index(b, i, k);
    changed = true;
  }
  return changed;
}

}  // namespace

Balancing balance(const MatrixXd& m) {
  if (m.rows() != m.cols()) throw std::invalid_argument("balance: matrix is not square");
  if (!m.allFinite()) throw std::invalid_argument("balance: matrix has a non-finite entry");
  Balancing b{m, Eigen::VectorXi::Zero(m.rows())};
  for (int s = 0; s < kMaxSweeps && sweep(b); ++s) {
  }
  return b;
}

MatrixXd balanced_exponential(const MatrixXd& m) {
  if (m.size() == 0) return m;
  const Balancing b = balance(m);
  MatrixXd e = b.balanced.exp();
  // e^m = D e^{D⁻¹ m D} D⁻¹: entry (i, j) times 2^(e_i - e_j), exact.
  for (Index j = 0; j < e.cols(); ++j)
    for (Index i = 0; i < e.rows(); ++i)
      e(i, j) = std::ldexp(e(i, j), b.exponents(i) - b.exponents(j));
  return e;
}

}  // namespace flexloop::plant::lti
