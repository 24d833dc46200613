// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/stable_covariance.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "plant/lti/frequency_response.hpp"

extern "C" {
// LAPACK: ordered real Schur form; quasi-triangular Sylvester equation.
void dgees_(const char* jobvs, const char* sort, int (*select)(const double*, const double*),
            const int* n, double* a, const int* lda, int* sdim, double* wr, double* wi, double* vs,
            const int* ldvs, double* work, const int* lwork, int* bwork, int* info, std::size_t,
            std::size_t);
void dtrsyl_(const char* trana, const char* tranb, const int* isgn, const int* m, const int* n,
             const double* a, const int* lda, const double* b, const int* ldb, double* c,
             const int* ldc, double* scale, int* info, std::size_t, std::size_t);
// SLICOT: the Cholesky factor of a convergent discrete Lyapunov equation's solution
// (Hammarling's method), here on a matrix already in real Schur form (FACT = 'F').
void sb03od_(const char* dico, const char* fact, const char* trans, const int* n, const int* m,
             double* a, const int* lda, double* q, const int* ldq, double* b, const int* ldb,
             double* scale, double* wr, double* wi, double* dwork, const int* ldwork, int* info,
             std::size_t, std::size_t, std::size_t);
}

namespace flexloop::plant::lti {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;

// dgees's selection takes no context: the tolerance of the call under way, per thread.
thread_local double inside_radius = 1;

int strictly_inside(const double* re, const double* im) {
  return std::hypot(*re, *im) < inside_radius ? 1 : 0;
}

struct OrderedSchur {
  MatrixXd S, Q;  // balanced A = Q S Q^T, the modes inside first
  int inside = 0;
  double slowest_inside = 1;  // min (1 - |lambda|) over the modes inside
};

// The ordered real Schur form of `a` (balanced), its modes with |lambda| < 1 - tol first.
OrderedSchur ordered_schur(MatrixXd a, double tol) {
  const int n = static_cast<int>(a.rows());
  OrderedSchur o;
  o.Q.resize(n, n);
  std::vector<double> wr(static_cast<std::size_t>(n)), wi(wr.size());
  std::vector<int> bwork(wr.size());
  int lwork = std::max(1, 6 * n), info = 0;
  std::vector<double> work(static_cast<std::size_t>(lwork));
  inside_radius = 1 - tol;
  dgees_("V", "S", strictly_inside, &n, a.data(), &n, &o.inside, wr.data(), wi.data(), o.Q.data(),
         &n, work.data(), &lwork, bwork.data(), &info, 1, 1);
  if (info == n + 2) throw std::invalid_argument("the modes on the unit circle are not resolved");
  if (info != 0) throw std::invalid_argument("the loop's eigenvalues did not converge");
  for (std::size_t i = 0; i < wr.size(); ++i) {
    const double radius = std::hypot(wr[i], wi[i]);
    if (radius > 1 + tol) throw std::invalid_argument("the loop is unstable");
    if (radius < 1 - tol) o.slowest_inside = std::min(o.slowest_inside, 1 - radius);
  }
  o.S = std::move(a);
  return o;
}

// X with S11 X - X S22 = -S12: the modes on the circle's invariant subspace is [X; I].
MatrixXd decoupling(const OrderedSchur& o) {
  const int k = o.inside, m = static_cast<int>(o.S.rows()) - o.inside, isgn = -1;
  MatrixXd s11 = o.S.topLeftCorner(k, k), s22 = o.S.bottomRightCorner(m, m);
  MatrixXd x = -o.S.topRightCorner(k, m);
  double scale = 1;
  int info = 0;
  dtrsyl_("N", "N", &isgn, &k, &m, s11.data(), &k, s22.data(), &m, x.data(), &k, &scale, &info, 1,
          1);
  if (info < 0 || !(scale > 0))
    throw std::invalid_argument("the modes on the unit circle are not resolved");
  return x / scale;
}

// U upper triangular with S11 (U U^T) S11^T - U U^T = -G G^T, S11 quasi-triangular with every
// eigenvalue inside the circle (SB03OD, TRANS = 'T': op(K) = K^T, X = U U^T).
MatrixXd lyapunov_factor_on_schur(const MatrixXd& s11, const MatrixXd& g) {
  const int k = static_cast<int>(s11.rows()), m = static_cast<int>(g.cols());
  MatrixXd a = s11, q = MatrixXd::Identity(k, k), b = MatrixXd::Zero(k, std::max(k, m));
  b.leftCols(m) = g;
  double scale = 1;
  std::vector<double> wr(static_cast<std::size_t>(k)), wi(wr.size());
  int ldwork = std::max(1, 4 * k + std::min(k, m)), info = 0;
  ldwork = std::max(ldwork, k * std::max(k, m));  // room for the blocked factorisations
  std::vector<double> dwork(static_cast<std::size_t>(ldwork));
  sb03od_("D", "F", "T", &k, &m, a.data(), &k, q.data(), &k, b.data(), &k, &scale, wr.data(),
          wi.data(), dwork.data(), &ldwork, &info, 1, 1, 1);
  if (info == 3) throw std::invalid_argument("the modes on the unit circle are not resolved");
  if (info < 0 || info > 1 || !(scale > 0))
    throw std::invalid_argument("the stationary covariance did not settle");
  // SB03OD leaves rubbish below the diagonal of its workspace-sized array: U is upper.
  return b.leftCols(k).triangularView<Eigen::Upper>().toDenseMatrix() / scale;
}

}  // namespace

StableCovariance stable_covariance(const MatrixXd& A, const MatrixXd& B, double tol) {
  const Index n = A.rows();
  if (A.cols() != n || B.rows() != n)
    throw std::invalid_argument("stable covariance: the sizes of A and B do not close");
  StableCovariance c;
  c.P = MatrixXd::Zero(n, n);
  c.factor = MatrixXd::Zero(n, 0);
  c.stable_noise = MatrixXd::Zero(n, B.cols());
  if (n == 0) return c;
  const Eigen::VectorXd t = balancing_scaling(A);
  const OrderedSchur o = ordered_schur(t.cwiseInverse().asDiagonal() * A * t.asDiagonal(), tol);
  const Index k = o.inside, m = n - k;
  const MatrixXd b = o.Q.transpose() * (t.cwiseInverse().asDiagonal() * B);
  MatrixXd g = b.topRows(k);
  c.on_circle = m;
  if (m > 0) {
    const MatrixXd x = decoupling(o);
    g -= x * b.bottomRows(m);
    // The noise's part on the circle, Q [X B2; B2] in x's coordinates.
    MatrixXd on(n, B.cols());
    on << x * b.bottomRows(m), b.bottomRows(m);
    c.driven = (t.asDiagonal() * (o.Q * on)).norm() / std::max(B.norm(), 1e-300);
  }
  c.stable_noise = t.asDiagonal() * (o.Q.leftCols(k) * g);
  if (k == 0) return c;
  const MatrixXd u = lyapunov_factor_on_schur(o.S.topLeftCorner(k, k), g);
  c.factor = t.asDiagonal() * (o.Q.leftCols(k) * u);
  c.sensitivity =
      std::numeric_limits<double>::epsilon() * o.S.topLeftCorner(k, k).norm() / o.slowest_inside;
  c.P = c.factor * c.factor.transpose();
  return c;
}

}  // namespace flexloop::plant::lti
