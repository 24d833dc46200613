#include "plant/lti/stable_covariance.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
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
// SLICOT: the discrete Lyapunov equation on a quasi-triangular matrix (SB03MD's kernel).
void sb03mx_(const char* trana, const int* n, const double* a, const int* lda, double* c,
             const int* ldc, double* scale, double* dwork, int* info, std::size_t);
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
  for (std::size_t i = 0; i < wr.size(); ++i)
    if (std::hypot(wr[i], wi[i]) > 1 + tol) throw std::invalid_argument("the loop is unstable");
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

// P11 with S11 P11 S11^T - P11 = -G G^T, S11 quasi-triangular.
MatrixXd lyapunov_on_schur(const MatrixXd& s11, const MatrixXd& g) {
  const int k = static_cast<int>(s11.rows());
  MatrixXd c = -g * g.transpose();
  double scale = 1;
  std::vector<double> dwork(static_cast<std::size_t>(2 * k));
  int info = 0;
  // op(A) = A^T: (A^T)^T X A^T - X = A X A^T - X = scale C.
  sb03mx_("T", &k, s11.data(), &k, c.data(), &k, &scale, dwork.data(), &info, 1);
  if (info < 0 || !(scale > 0))
    throw std::invalid_argument("the stationary covariance did not settle");
  return c / scale;
}

}  // namespace

StableCovariance stable_covariance(const MatrixXd& A, const MatrixXd& B, double tol) {
  const Index n = A.rows();
  if (A.cols() != n || B.rows() != n)
    throw std::invalid_argument("stable covariance: the sizes of A and B do not close");
  StableCovariance c;
  c.P = MatrixXd::Zero(n, n);
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
  if (k == 0) return c;
  const MatrixXd p11 = lyapunov_on_schur(o.S.topLeftCorner(k, k), g);
  const MatrixXd tq1 = t.asDiagonal() * o.Q.leftCols(k);
  c.P = tq1 * (0.5 * (p11 + p11.transpose())) * tq1.transpose();
  return c;
}

}  // namespace flexloop::plant::lti
