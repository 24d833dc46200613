// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/model_reduction.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"

// SLICOT (Fortran 77; gfortran passes each CHARACTER argument's length after the others).
extern "C" void ab09md_(const char* dico, const char* job, const char* equil, const char* ordsel,
                        const int* n, const int* m, const int* p, int* nr, const double* alpha,
                        double* a, const int* lda, double* b, const int* ldb, double* c,
                        const int* ldc, int* ns, double* hsv, const double* tol, int* iwork,
                        double* dwork, const int* ldwork, int* iwarn, int* info, std::size_t,
                        std::size_t, std::size_t, std::size_t);

namespace flexloop::plant::lti {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using numeric::kEps;
using numeric::kTwoPi;

struct Mode {
  Index start = 0;  // first state in the modal coordinates
  int size = 1;     // 1: real pole, 2: a pair; the poles at the origin: all of them, one block
  std::complex<double> pole;
  bool always_kept = false;  // at the origin or unstable
};

// A in real block-diagonal modal coordinates: x = T z, Am = T^-1 A T (its off-block entries are
// round-off and are dropped where blocks are taken), Bm = T^-1 B, Cm = C T.
struct RealModes {
  MatrixXd T, Am, Bm, Cm;
  std::vector<Mode> modes;                 // by |pole| ascending
  std::vector<std::string> origin_labels;  // the origin block's states, when they are physical
};

// An orthonormal basis of the invariant subspace of the eigenvalue 0 (its generalised eigenvectors,
// Jordan chains included) grown a chain link at a time: the vectors x with A x in the span found
// so far, from the SVD of (I - K K^T) A. Not the null space of A^m, whose entries span
// ||A||^m: a stiff model's (10^10 in SI units) would drown the small ones.
MatrixXd origin_subspace(const MatrixXd& A, Index count) {
  const Index n = A.rows();
  MatrixXd K(n, 0);
  while (K.cols() < count) {
    const MatrixXd M = A - K * (K.transpose() * A);
    Eigen::JacobiSVD<MatrixXd> svd(M, Eigen::ComputeFullV);
    const auto& sv = svd.singularValues();
    Index dims = 0;
    while (dims < n && sv(n - 1 - dims) <= 1e-12 * sv(0)) ++dims;
    if (dims <= K.cols()) break;  // no longer growing
    K = svd.matrixV().rightCols(std::min(dims, count));
  }
  return K;
}

RealModes real_modes(const StateSpace& s, double max_condition,
                     const std::vector<std::string>& origin_states = {}) {
  s.validate();
  const Index n = s.nx();
  const Eigen::VectorXd t = balancing_scaling(s.A);
  const MatrixXd Ab = t.cwiseInverse().asDiagonal() * s.A * t.asDiagonal();
  Eigen::EigenSolver<MatrixXd> es(Ab);
  if (es.info() != Eigen::Success)
    throw std::invalid_argument("modal truncation: the eigen-decomposition did not converge");
  const Eigen::VectorXcd lambda = es.eigenvalues();
  const Eigen::MatrixXcd V = es.eigenvectors();
  const double radius = n > 0 ? lambda.cwiseAbs().maxCoeff() : 0;
  const double origin = std::sqrt(kEps) * std::max(radius, 1.0);

  RealModes r;
  MatrixXd Tb(n, n);
  std::vector<Mode> modes;
  Index col = 0;
  // The poles at the origin (rigid bodies, the floor's double integrators: often Jordan blocks,
  // which have no eigenvector basis) as one block: the null space of Ab^m, m their count, which
  // is their invariant subspace whatever their Jordan structure.
  Index at_origin = 0;
  MatrixXd to_named;  // the origin block's change to the named states' coordinates, if any
  for (Index k = 0; k < n; ++k) at_origin += std::abs(lambda(k)) <= origin;
  if (at_origin > 0) {
    const MatrixXd K = origin_subspace(Ab, at_origin);
    if (K.cols() != at_origin)
      throw std::invalid_argument(
          "modal truncation: the " + std::to_string(at_origin) +
          " poles at the origin do not span an invariant subspace of that size (found " +
          std::to_string(K.cols()) + "); use balanced truncation");
    Tb.leftCols(at_origin) = K;
    // In the coordinates of the named states when they span the block: the stable modes have no
    // component in states that only the inputs drive (the floor's position and velocity), so
    // those states are then exactly the block's coordinates.
    if (static_cast<Index>(origin_states.size()) == at_origin) {
      MatrixXd rows(at_origin, at_origin);
      Index found = 0;
      for (const std::string& label : origin_states)
        for (Index i = 0; i < n; ++i)
          if (s.states[static_cast<std::size_t>(i)] == label) rows.row(found++) = t(i) * K.row(i);
      if (found == at_origin) {
        Eigen::JacobiSVD<MatrixXd> rsv(rows);
        const auto& v = rsv.singularValues();
        if (v(at_origin - 1) > 1e-8 * v(0)) {
          to_named = rows;  // applied once the decomposition is done (below)
          r.origin_labels = origin_states;
        }
      }
    }
    modes.push_back(
        {.start = 0, .size = static_cast<int>(at_origin), .pole = 0, .always_kept = true});
    col = at_origin;
  }
  for (Index k = 0; k < n; ++k) {
    const std::complex<double> l = lambda(k);
    if (l.imag() < 0 || std::abs(l) <= origin) continue;  // a conjugate already taken; the origin
    Mode m{.start = col, .size = l.imag() > 0 ? 2 : 1, .pole = l};
    m.always_kept = l.real() >= 0;
    const Eigen::VectorXcd v = V.col(k).normalized();
    Tb.col(col++) = v.real();
    if (m.size == 2) Tb.col(col++) = v.imag();
    modes.push_back(m);
  }
  if (col != n)
    throw std::invalid_argument("modal truncation: the eigenvalues of A do not come in pairs");
  Eigen::JacobiSVD<MatrixXd> svd(Tb);
  const auto& sv = svd.singularValues();
  if (n > 0 && !(sv(n - 1) > 0 && sv(0) / sv(n - 1) <= max_condition))
    throw std::invalid_argument(
        "modal truncation: A is defective or nearly so away from the origin (eigenvector "
        "condition " +
        std::to_string(sv(n - 1) > 0 ? sv(0) / sv(n - 1) : INFINITY) +
        "): repeated poles without independent modes have no modal form; use balanced "
        "truncation");
  const Eigen::PartialPivLU<MatrixXd> lu(Tb);
  r.Am = lu.solve(Ab * Tb);
  r.Bm = lu.solve(t.cwiseInverse().asDiagonal() * s.B);
  r.Cm = s.C * t.asDiagonal() * Tb;
  r.T = t.asDiagonal() * Tb;
  // The origin block in the named states' coordinates z' = R z (R: their rows of T): a change of
  // basis inside the block, after the decomposition, so that it neither enters the eigenvector
  // condition above nor the solves (the named states' balancing scales can be far apart).
  if (to_named.size() > 0) {
    const Index m = to_named.rows();
    const MatrixXd back = to_named.inverse();  // m x m, checked well-conditioned above
    r.Am.topLeftCorner(m, m) = (to_named * r.Am.topLeftCorner(m, m) * back).eval();
    r.Bm.topRows(m) = (to_named * r.Bm.topRows(m)).eval();
    r.Cm.leftCols(m) = (r.Cm.leftCols(m) * back).eval();
    r.T.leftCols(m) = (r.T.leftCols(m) * back).eval();
  }
  std::stable_sort(modes.begin(), modes.end(), [](const Mode& a, const Mode& b) {
    return std::abs(a.pole) < std::abs(b.pole);
  });
  r.modes = std::move(modes);
  return r;
}

// The mode's own transfer at s: Cm_k (sI - Am_k)^-1 Bm_k.
Eigen::MatrixXcd mode_transfer(const RealModes& r, const Mode& m, std::complex<double> s) {
  const MatrixXd a = r.Am.block(m.start, m.start, m.size, m.size);
  const Eigen::MatrixXcd sia =
      s * Eigen::MatrixXcd::Identity(m.size, m.size) - a.cast<std::complex<double>>();
  return r.Cm.middleCols(m.start, m.size).cast<std::complex<double>>() *
         sia.partialPivLu().solve(r.Bm.middleRows(m.start, m.size).cast<std::complex<double>>());
}

// Relative contribution of each mode (see the header); +inf for the modes always kept. band_hz
// [lo, hi] (hi = 0: no band): the grid and each mode's frequency are held inside it.
std::vector<double> contributions(const StateSpace& s, const RealModes& r,
                                  std::array<double, 2> band_hz) {
  std::vector<double> c(r.modes.size(), INFINITY);
  double lo = INFINITY, hi = 0;
  for (const Mode& m : r.modes)
    if (!m.always_kept) {
      lo = std::min(lo, std::abs(m.pole) / kTwoPi / 10);
      hi = std::max(hi, std::abs(m.pole) / kTwoPi * 10);
    }
  if (hi == 0) return c;
  const bool banded = band_hz[1] > 0;
  if (banded) lo = band_hz[0], hi = band_hz[1];
  const auto in_band = [&](double f) { return banded ? std::clamp(f, lo, hi) : f; };
  std::vector<double> f = log_frequency_grid_hz(lo, hi, 200);
  for (const Mode& m : r.modes)
    if (!m.always_kept && m.size == 2) f.push_back(in_band(std::abs(m.pole.imag()) / kTwoPi));
  MatrixXd peak = MatrixXd::Zero(s.ny(), s.nu());
  for (const Eigen::MatrixXcd& g : frequency_response(s, f)) peak = peak.cwiseMax(g.cwiseAbs());
  for (std::size_t k = 0; k < r.modes.size(); ++k) {
    const Mode& m = r.modes[k];
    if (m.always_kept) continue;
    const double f_mode = m.size == 2 ? std::abs(m.pole.imag()) / kTwoPi : 0;
    const std::complex<double> at(0, kTwoPi * (f_mode > 0 || banded ? in_band(f_mode) : 0));
    const MatrixXd g = mode_transfer(r, m, at).cwiseAbs();
    double worst = 0;
    for (Index i = 0; i < g.rows(); ++i)
      for (Index j = 0; j < g.cols(); ++j)
        if (peak(i, j) > 0) worst = std::max(worst, g(i, j) / peak(i, j));
    c[k] = worst;
  }
  return c;
}

std::vector<std::string> numbered(const std::string& prefix, Index n) {
  std::vector<std::string> v;
  for (Index k = 1; k <= n; ++k) v.push_back(prefix + std::to_string(k));
  return v;
}

}  // namespace

std::vector<ModeContribution> modal_contributions(const StateSpace& sys,
                                                  const ModalTruncationOptions& o) {
  const RealModes r = real_modes(sys, o.max_condition);
  const std::vector<double> c = contributions(sys, r, {o.band_low_hz, o.band_hz});
  std::vector<ModeContribution> out;
  for (std::size_t k = 0; k < r.modes.size(); ++k) {
    const auto& p = r.modes[k].pole;
    const double w = std::abs(p);
    // The origin block's pole is set to exactly 0 (real_modes): it has no damping.
    const bool origin = w == 0;
    out.push_back({.frequency_hz = w / kTwoPi,
                   .damping = origin ? std::numeric_limits<double>::quiet_NaN() : -p.real() / w,
                   .states = r.modes[k].size,
                   .at_origin = origin,
                   .contribution = c[k]});
  }
  return out;
}

ReducedModel modal_truncation(const StateSpace& sys, const ModalTruncationOptions& o) {
  if (o.order < 0 && !(o.below_hz > 0 && std::isfinite(o.below_hz)))
    throw std::invalid_argument("modal truncation: give an order (>= 0) or a frequency (> 0)");
  const RealModes r = real_modes(sys, o.max_condition, o.origin_states);
  const std::vector<double> c = contributions(sys, r, {o.band_low_hz, o.band_hz});
  std::vector<bool> keep(r.modes.size(), false);
  ReducedModel out;
  Index kept = 0;
  for (std::size_t k = 0; k < r.modes.size(); ++k)
    if (r.modes[k].always_kept) {
      keep[k] = true;
      kept += r.modes[k].size;
      out.kept_unstable += r.modes[k].size;
    }
  if (o.order >= 0) {
    std::vector<std::size_t> by(r.modes.size());
    std::iota(by.begin(), by.end(), 0);
    std::stable_sort(by.begin(), by.end(), [&](auto a, auto b) { return c[a] > c[b]; });
    for (const std::size_t k : by)
      if (!keep[k] && kept + r.modes[k].size <= o.order) {
        keep[k] = true;
        kept += r.modes[k].size;
      }
  } else {
    for (std::size_t k = 0; k < r.modes.size(); ++k)
      if (!keep[k] && std::abs(r.modes[k].pole) / kTwoPi < o.below_hz) {
        keep[k] = true;
        kept += r.modes[k].size;
      }
  }
  StateSpace& s = out.sys;
  s.A = MatrixXd::Zero(kept, kept);
  s.B.resize(kept, sys.nu());
  s.C.resize(sys.ny(), kept);
  s.D = sys.D;
  Index at = 0;
  for (std::size_t k = 0; k < r.modes.size(); ++k) {
    const Mode& m = r.modes[k];
    if (keep[k]) {
      const bool physical = m.pole == 0.0 && !r.origin_labels.empty();
      for (int i = 0; i < m.size; ++i)
        s.states.push_back(physical ? r.origin_labels[static_cast<std::size_t>(i)]
                                    : "mode:" + std::to_string(at + i + 1));
      s.A.block(at, at, m.size, m.size) = r.Am.block(m.start, m.start, m.size, m.size);
      s.B.middleRows(at, m.size) = r.Bm.middleRows(m.start, m.size);
      s.C.middleCols(at, m.size) = r.Cm.middleCols(m.start, m.size);
      at += m.size;
    } else if (o.dc_correction) {
      s.D -= r.Cm.middleCols(m.start, m.size) * r.Am.block(m.start, m.start, m.size, m.size)
                                                    .partialPivLu()
                                                    .solve(r.Bm.middleRows(m.start, m.size));
    }
  }
  s.inputs = sys.inputs;
  s.outputs = sys.outputs;
  out.method = o.dc_correction ? "modal-dc" : "modal";
  out.error_bound = NAN;
  return out;
}

namespace {

// One call of AB09MD (continuous, square-root B&T with scaling, fixed order): the reduced
// matrices in the leading parts of a, b, c; nr, ns and the stable part's Hankel singular values.
struct Ab09md {
  MatrixXd a, b, c;
  int nr = 0, ns = 0;
  std::vector<double> hsv;
};

Ab09md ab09md(const StateSpace& sys, int order, double alpha) {
  const int n = static_cast<int>(sys.nx()), m = static_cast<int>(sys.nu()),
            p = static_cast<int>(sys.ny());
  Ab09md r{sys.A, sys.B, sys.C, std::min(order, n), 0, std::vector<double>(std::size_t(n))};
  const int lda = std::max(1, n), ldb = std::max(1, n), ldc = std::max(1, p);
  if (r.c.rows() == 0) r.c.resize(1, n);  // LDC >= 1
  const int ldwork = std::max(1, n * (2 * n + std::max({n, m, p}) + 5) + n * (n + 1) / 2);
  std::vector<double> dwork(static_cast<std::size_t>(ldwork));
  std::vector<int> iwork(static_cast<std::size_t>(n));
  int iwarn = 0, info = 0;
  const double tol = 0;
  ab09md_("C", "B", "S", "F", &n, &m, &p, &r.nr, &alpha, r.a.data(), &lda, r.b.data(), &ldb,
          r.c.data(), &ldc, &r.ns, r.hsv.data(), &tol, iwork.data(), dwork.data(), &ldwork, &iwarn,
          &info, 1, 1, 1, 1);
  if (info != 0) {
    const char* what = info == 1   ? "the reduction of A to real Schur form failed"
                       : info == 2 ? "the separation of the stable part failed"
                       : info == 3 ? "the Hankel singular values could not be computed"
                                   : "an argument was wrong";
    throw std::runtime_error("balanced truncation (SLICOT AB09MD, INFO = " + std::to_string(info) +
                             "): " + what);
  }
  return r;
}

}  // namespace

ReducedModel balanced_truncation(const StateSpace& sys, int order) {
  sys.validate();
  if (order < 0) throw std::invalid_argument("balanced truncation: the order must be >= 0");
  const int n = static_cast<int>(sys.nx());
  ReducedModel out;
  out.method = "balanced";
  if (n == 0) {
    out.sys = sys;
    return out;
  }
  // The stability boundary AB09MD separates at: half-way between the origin and the least damped
  // stable pole that is not at the origin, so that the poles at the origin (whose computed real
  // parts scatter by round-off, ~sqrt(eps) of the fastest for a Jordan block) are kept whole and
  // a lightly damped mode is not.
  const Eigen::VectorXcd poles = Eigen::EigenSolver<MatrixXd>(sys.A, false).eigenvalues();
  const double origin = std::sqrt(kEps) * std::max(poles.cwiseAbs().maxCoeff(), 1.0);
  double slowest = -INFINITY;
  for (const auto& l : poles)
    if (std::abs(l) > origin && l.real() < 0) slowest = std::max(slowest, l.real());
  const double alpha = std::isfinite(slowest) ? slowest / 2 : -origin;
  // AB09MD computes the Hankel singular values only when it reduces the stable part, so they
  // come from a call at the full order.
  const Ab09md all = ab09md(sys, n, alpha);
  const Ab09md r = ab09md(sys, order, alpha);
  const int nu = n - all.ns;  // the part kept whole
  out.kept_unstable = nu;
  out.hankel_singular_values = Eigen::Map<const Eigen::VectorXd>(all.hsv.data(), all.ns);
  const int kept_stable = std::max(r.nr - nu, 0);
  out.error_bound = 2 * out.hankel_singular_values.tail(all.ns - kept_stable).sum();
  out.sys.A = r.a.topLeftCorner(r.nr, r.nr);
  out.sys.B = r.b.topRows(r.nr);
  out.sys.C = r.c.topLeftCorner(sys.ny(), r.nr);
  out.sys.D = sys.D;
  out.sys.states = numbered("balanced:", r.nr);
  out.sys.inputs = sys.inputs;
  out.sys.outputs = sys.outputs;
  return out;
}

}  // namespace flexloop::plant::lti
