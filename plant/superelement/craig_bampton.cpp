// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/craig_bampton.hpp"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>
#include <Eigen/CholmodSupport>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "numeric/constants.hpp"

namespace flexloop::plant::superelement {

namespace {

using Cholesky = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;

// y = (A - sigma B)^-1 x, the shifted pencil factored once by CHOLMOD: Spectra's operator for
// shift-invert (its own uses SparseLU, which fills in far more on an FE matrix).
class CholmodShiftInvert {
 public:
  using Scalar = double;
  CholmodShiftInvert(const SparseMatrix& a, const SparseMatrix& b) : a_(a), b_(b) {}
  Eigen::Index rows() const { return a_.rows(); }
  Eigen::Index cols() const { return a_.cols(); }
  /// Factors A - sigma B (once per sigma); false when it is not positive definite.
  bool factor(double sigma) {
    if (factored_ && sigma == sigma_) return true;  // the solver asks again for each batch
    factored_ = false;
    if (sigma == 0) {
      solver_.compute(a_);
    } else {
      const SparseMatrix shifted = a_ - sigma * b_;
      solver_.compute(shifted);
    }
    if (solver_.info() != Eigen::Success) return false;
    sigma_ = sigma;
    factored_ = true;
    return true;
  }
  void set_shift(double sigma) {
    if (!factor(sigma))
      throw std::domain_error("K - sigma M is not positive definite at sigma = " +
                              std::to_string(sigma) + " (M not positive definite?)");
  }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<Eigen::VectorXd>(y, a_.rows()) =
        solver_.solve(Eigen::Map<const Eigen::VectorXd>(x, a_.rows()));
  }
  const Cholesky& factorisation() const { return solver_; }

 private:
  const SparseMatrix& a_;
  const SparseMatrix& b_;
  Cholesky solver_;
  double sigma_ = 0;
  bool factored_ = false;
};

// The shift-invert operator with the modes found so far (V, M-normalised) deflated:
// y = P op(P x), P = I - V V' M. Their eigenvalues become 0, so a later Lanczos batch finds the
// next modes instead of starting over and finding the same ones again.
class DeflatedShiftInvert {
 public:
  using Scalar = double;
  DeflatedShiftInvert(CholmodShiftInvert& op, const Eigen::MatrixXd& v, const Eigen::MatrixXd& mv)
      : op_(op), v_(v), mv_(mv) {}
  Eigen::Index rows() const { return op_.rows(); }
  Eigen::Index cols() const { return op_.cols(); }
  void set_shift(double sigma) { op_.set_shift(sigma); }
  void perform_op(const double* x, double* y) const {
    const Eigen::Index n = rows();
    Eigen::Map<const Eigen::VectorXd> xin(x, n);
    Eigen::Map<Eigen::VectorXd> yout(y, n);
    if (v_.cols() == 0) {
      op_.perform_op(x, y);
      return;
    }
    const Eigen::VectorXd projected = xin - v_ * (mv_.transpose() * xin);
    op_.perform_op(projected.data(), y);
    yout -= v_ * (mv_.transpose() * yout);
  }

 private:
  CholmodShiftInvert& op_;
  const Eigen::MatrixXd& v_;
  const Eigen::MatrixXd& mv_;
};

struct Modes {
  Eigen::VectorXd lambda;   ///< w^2, ascending
  Eigen::MatrixXd vectors;  ///< M-normalised
};

// Small pencils: every eigenpair, dense.
Modes dense_modes(const SparseMatrix& k, const SparseMatrix& m) {
  const Eigen::MatrixXd kd = k, md = m;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(kd, md);
  if (ges.info() != Eigen::Success)
    throw std::domain_error("the mass matrix is not positive definite");
  return {ges.eigenvalues(), ges.eigenvectors()};
}

// The lowest `nev` eigenpairs by shift-invert Lanczos about sigma, of those not in `found`.
Modes lanczos_modes(CholmodShiftInvert& op, const SparseMatrix& m, const Modes& found,
                    Eigen::Index nev, double sigma) {
  const Eigen::MatrixXd mv = m * found.vectors;
  DeflatedShiftInvert deflated(op, found.vectors, mv);
  Spectra::SparseSymMatProd<double> bop(m);
  const Eigen::Index n = m.rows();
  const Eigen::Index ncv = std::min(n, std::max(2 * nev + 1, nev + 20));
  Spectra::SymGEigsShiftSolver<DeflatedShiftInvert, Spectra::SparseSymMatProd<double>,
                               Spectra::GEigsMode::ShiftInvert>
      eigs(deflated, bop, nev, ncv, sigma);
  eigs.init();
  // Ritz residuals to 1e-8 of the eigenvalue: an eigenvalue is then exact to ~1e-16 / gap, and
  // to 1e-8 in a cluster; 1e-10 took 43 solves instead of 26 for the 121 245-DOF bar's second
  // batch, each a pass over a 400 MB factor.
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-8, Spectra::SortRule::SmallestAlge);
  if (eigs.info() != Spectra::CompInfo::Successful)
    throw std::domain_error("the Lanczos iteration did not converge for " + std::to_string(nev) +
                            " modes");
  return {eigs.eigenvalues(), eigs.eigenvectors()};
}

// `found` and `batch`, the batch's vectors M-normalised, in ascending order.
Modes merged(const Modes& found, const Modes& batch, const SparseMatrix& m) {
  const Eigen::Index k = found.lambda.size(), b = batch.lambda.size();
  Eigen::VectorXd lambda(k + b);
  lambda << found.lambda, batch.lambda;
  Eigen::MatrixXd vectors(m.rows(), k + b);
  vectors << found.vectors, batch.vectors;
  for (Eigen::Index j = k; j < k + b; ++j)
    vectors.col(j) /= std::sqrt(vectors.col(j).dot(m * vectors.col(j)));
  std::vector<Eigen::Index> order(static_cast<std::size_t>(k + b));
  for (std::size_t j = 0; j < order.size(); ++j) order[j] = static_cast<Eigen::Index>(j);
  std::sort(order.begin(), order.end(),
            [&](Eigen::Index p, Eigen::Index q) { return lambda(p) < lambda(q); });
  Modes out{Eigen::VectorXd(k + b), Eigen::MatrixXd(m.rows(), k + b)};
  for (Eigen::Index j = 0; j < k + b; ++j) {
    out.lambda(j) = lambda(order[static_cast<std::size_t>(j)]);
    out.vectors.col(j) = vectors.col(order[static_cast<std::size_t>(j)]);
  }
  return out;
}

// Those of `all` below lambda_max (at most `at_most`), their vectors M-normalised.
Modes below(const Modes& all, const SparseMatrix& m, double lambda_max, Eigen::Index at_most) {
  Eigen::Index count = 0;
  while (count < all.lambda.size() && count < at_most && all.lambda(count) <= lambda_max) ++count;
  Modes out{all.lambda.head(count), all.vectors.leftCols(count)};
  for (Eigen::Index j = 0; j < count; ++j) {
    const double norm = std::sqrt(out.vectors.col(j).dot(m * out.vectors.col(j)));
    out.vectors.col(j) /= norm;
  }
  return out;
}

// How many more modes than the `found` (ascending, not past lambda_max) lie below lambda_max:
// their count N(lambda) extrapolated as a power law through its upper half, with 25 % margin,
// at least 4: a second batch sized so costs half a doubled one on the 121 245-DOF bar.
Eigen::Index more_modes(const Eigen::VectorXd& found, double lambda_max) {
  const Eigen::Index k = found.size(), h = k / 2;
  double estimate = 2.0 * static_cast<double>(k);
  if (h >= 2 && found(h - 1) > 0 && found(k - 1) > found(h - 1)) {
    const double p = std::log(static_cast<double>(k) / static_cast<double>(h)) /
                     std::log(found(k - 1) / found(h - 1));
    estimate =
        static_cast<double>(k) * std::pow(lambda_max / found(k - 1), std::clamp(p, 0.5, 2.0));
  }
  return std::max<Eigen::Index>(4, static_cast<Eigen::Index>(std::ceil(1.25 * estimate)) - k);
}

// Every mode below lambda_max (at most `at_most`): batches of Lanczos modes, each on the
// operator with the earlier batches' modes deflated, until one reaches past the cut-off. `op`
// is factored at `sigma`, below the lowest mode (a free body's 0 included).
Modes modes_below(CholmodShiftInvert& op, const SparseMatrix& m, double lambda_max,
                  Eigen::Index at_most, double sigma) {
  const Eigen::Index n = m.rows();
  Modes found{Eigen::VectorXd(0), Eigen::MatrixXd(n, 0)};
  Eigen::Index nev = std::min<Eigen::Index>({16, at_most, n - 2});
  for (;;) {
    const Modes batch = lanczos_modes(op, m, found, nev, sigma);
    found = merged(found, batch, m);
    const Eigen::Index left = std::min(at_most, n - 2) - found.lambda.size();
    if (batch.lambda.maxCoeff() > lambda_max || left <= 0)
      return below(found, m, lambda_max, at_most);
    nev = std::min(more_modes(found.lambda, lambda_max), left);
  }
}

Modes modes_below(const SparseMatrix& k, const SparseMatrix& m, double lambda_max,
                  Eigen::Index at_most) {
  if (k.rows() <= 200) return below(dense_modes(k, m), m, lambda_max, at_most);
  CholmodShiftInvert op(k, m);
  const double sigma = -1e-4 * lambda_max;
  op.set_shift(sigma);
  return modes_below(op, m, lambda_max, at_most, sigma);
}

// Rows (and columns) of A picked by `rows` and `cols`, each full index -> its index in the block
// or -1. Built in place column by column (no triplets, no sort): one pass to count, one to copy.
SparseMatrix block(const SparseMatrix& a, const std::vector<int>& rows, Eigen::Index nrows,
                   const std::vector<int>& cols, Eigen::Index ncols) {
  Eigen::VectorXi count = Eigen::VectorXi::Zero(ncols);
  for (int c = 0; c < a.outerSize(); ++c)
    if (const int bc = cols[static_cast<std::size_t>(c)]; bc >= 0)
      for (SparseMatrix::InnerIterator it(a, c); it; ++it)
        count(bc) += rows[static_cast<std::size_t>(it.row())] >= 0;
  SparseMatrix b(nrows, ncols);
  b.reserve(count);
  for (int c = 0; c < a.outerSize(); ++c)
    if (const int bc = cols[static_cast<std::size_t>(c)]; bc >= 0)
      for (SparseMatrix::InnerIterator it(a, c); it; ++it)
        if (const int r = rows[static_cast<std::size_t>(it.row())]; r >= 0)
          b.insert(r, bc) = it.value();  // in order when `rows` keeps the order: O(1)
  b.makeCompressed();
  return b;
}

void check_input(const SparseMatrix& k, const SparseMatrix& m,
                 const std::vector<Eigen::Index>& interface, double up_to_hz) {
  const Eigen::Index n = k.rows();
  if (k.cols() != n || m.rows() != n || m.cols() != n)
    throw std::invalid_argument("K is " + std::to_string(n) + " x " + std::to_string(k.cols()) +
                                ", M " + std::to_string(m.rows()) + " x " +
                                std::to_string(m.cols()) + ": they must be square, of one size");
  std::vector<bool> seen(static_cast<std::size_t>(n), false);
  for (const Eigen::Index r : interface) {
    if (r < 0 || r >= n)
      throw std::invalid_argument("interface row " + std::to_string(r) + " is outside the " +
                                  std::to_string(n) + " rows");
    if (seen[static_cast<std::size_t>(r)])
      throw std::invalid_argument("interface row " + std::to_string(r) + " is given twice");
    seen[static_cast<std::size_t>(r)] = true;
  }
  if (!(up_to_hz > 0 && std::isfinite(up_to_hz)))
    throw std::invalid_argument("the cut-off frequency must be a finite number above 0 Hz");
}

}  // namespace

Eigen::VectorXd sparse_natural_frequencies_hz(const SparseMatrix& k, const SparseMatrix& m,
                                              double up_to_hz, Eigen::Index at_most) {
  check_input(k, m, {}, up_to_hz);
  const double lambda_max = std::pow(numeric::kTwoPi * up_to_hz, 2);
  const Modes modes = modes_below(k, m, lambda_max, at_most);
  return modes.lambda.cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
}

CraigBampton craig_bampton(const SparseMatrix& k, const SparseMatrix& m,
                           const std::vector<Eigen::Index>& interface, double up_to_hz,
                           int residual_block_solves) {
  check_input(k, m, interface, up_to_hz);
  const Eigen::Index n = k.rows(), nb = static_cast<Eigen::Index>(interface.size()), ni = n - nb;
  std::vector<int> to_b(static_cast<std::size_t>(n), -1), to_i(static_cast<std::size_t>(n), -1);
  for (Eigen::Index j = 0; j < nb; ++j)
    to_b[static_cast<std::size_t>(interface[static_cast<std::size_t>(j)])] = static_cast<int>(j);
  int next = 0;
  for (std::size_t r = 0; r < to_b.size(); ++r)
    if (to_b[r] < 0) to_i[r] = next++;
  const SparseMatrix kii = block(k, to_i, ni, to_i, ni), mii = block(m, to_i, ni, to_i, ni);
  const SparseMatrix kib = block(k, to_i, ni, to_b, nb), mib = block(m, to_i, ni, to_b, nb);
  const Eigen::MatrixXd kbb = block(k, to_b, nb, to_b, nb), mbb = block(m, to_b, nb, to_b, nb);

  // K_ii, positive definite with the interface held, is factored once: for Psi and as the
  // shift-invert operator at sigma = 0.
  CholmodShiftInvert kii_op(kii, mii);
  if (!kii_op.factor(0.0))
    throw std::domain_error(
        "the body moves with its interface held still (K_ii is not positive "
        "definite): hold it in the FE tool or add interface nodes");
  const Eigen::MatrixXd psi = -kii_op.factorisation().solve(Eigen::MatrixXd(kib));
  const double lambda_max = std::pow(numeric::kTwoPi * up_to_hz, 2);
  const Modes phi = ni <= 200 ? below(dense_modes(kii, mii), mii, lambda_max, ni)
                              : modes_below(kii_op, mii, lambda_max, ni, 0.0);

  CraigBampton cb;
  cb.interface_dofs = nb;
  cb.fixed_interface_hz = phi.lambda.cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
  const Eigen::Index nm = phi.lambda.size();
  const Eigen::MatrixXd mii_psi = mii * psi;
  cb.K = Eigen::MatrixXd::Zero(nb + nm, nb + nm);
  cb.M = Eigen::MatrixXd::Zero(nb + nm, nb + nm);
  cb.K.topLeftCorner(nb, nb) = kbb + Eigen::MatrixXd(kib.transpose() * psi);
  cb.K.bottomRightCorner(nm, nm) = phi.lambda.asDiagonal();
  const Eigen::MatrixXd mib_psi = Eigen::MatrixXd(mib.transpose() * psi);
  cb.M.topLeftCorner(nb, nb) = mbb + mib_psi + mib_psi.transpose() + psi.transpose() * mii_psi;
  cb.M.topRightCorner(nb, nm) =
      Eigen::MatrixXd(mib.transpose() * phi.vectors) + mii_psi.transpose() * phi.vectors;
  cb.M.bottomLeftCorner(nm, nb) = cb.M.topRightCorner(nb, nm).transpose();
  cb.M.bottomRightCorner(nm, nm).setIdentity();
  if (residual_block_solves > 0) {
    const auto solve = [&](const Eigen::MatrixXd& x) -> Eigen::MatrixXd {
      return kii_op.factorisation().solve(x);
    };
    cb.residual =
        residual_moments(solve, mii, phi.vectors, phi.lambda, Eigen::MatrixXd(mib) + mii_psi,
                         lambda_max, residual_block_solves);
  }
  // Symmetric to rounding by construction; made exactly so for the eigen solvers downstream.
  cb.K = 0.5 * (cb.K + cb.K.transpose()).eval();
  cb.M = 0.5 * (cb.M + cb.M.transpose()).eval();
  return cb;
}

}  // namespace flexloop::plant::superelement
