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
  void set_shift(double sigma) {
    if (factored_ && sigma == sigma_) return;  // the solver asks again for each batch
    const SparseMatrix shifted = a_ - sigma * b_;
    solver_.compute(shifted);
    if (solver_.info() != Eigen::Success)
      throw std::domain_error("K - sigma M is not positive definite at sigma = " +
                              std::to_string(sigma) + " (M not positive definite?)");
    sigma_ = sigma;
    factored_ = true;
  }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<Eigen::VectorXd>(y, a_.rows()) =
        solver_.solve(Eigen::Map<const Eigen::VectorXd>(x, a_.rows()));
  }

 private:
  const SparseMatrix& a_;
  const SparseMatrix& b_;
  Cholesky solver_;
  double sigma_ = 0;
  bool factored_ = false;
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

// The lowest `nev` eigenpairs by shift-invert Lanczos about sigma.
Modes lanczos_modes(CholmodShiftInvert& op, const SparseMatrix& m, Eigen::Index nev, double sigma) {
  Spectra::SparseSymMatProd<double> bop(m);
  const Eigen::Index n = m.rows();
  const Eigen::Index ncv = std::min(n, std::max(2 * nev + 1, nev + 20));
  Spectra::SymGEigsShiftSolver<CholmodShiftInvert, Spectra::SparseSymMatProd<double>,
                               Spectra::GEigsMode::ShiftInvert>
      eigs(op, bop, nev, ncv, sigma);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10, Spectra::SortRule::SmallestAlge);
  if (eigs.info() != Spectra::CompInfo::Successful)
    throw std::domain_error("the Lanczos iteration did not converge for " + std::to_string(nev) +
                            " modes");
  return {eigs.eigenvalues(), eigs.eigenvectors()};
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

// Every mode below lambda_max (at most `at_most`): batches of Lanczos modes, doubled until one
// reaches past the cut-off. The shift sits below the lowest mode (a free body's 0 included).
Modes modes_below(const SparseMatrix& k, const SparseMatrix& m, double lambda_max,
                  Eigen::Index at_most) {
  const Eigen::Index n = k.rows();
  if (n <= 200) return below(dense_modes(k, m), m, lambda_max, at_most);
  const double sigma = -1e-4 * lambda_max;
  CholmodShiftInvert op(k, m);
  Eigen::Index nev = std::min<Eigen::Index>({16, at_most, n - 2});
  for (;;) {
    const Modes batch = lanczos_modes(op, m, nev, sigma);
    const bool past = batch.lambda(batch.lambda.size() - 1) > lambda_max;
    if (past || nev >= at_most || nev >= n - 2) return below(batch, m, lambda_max, at_most);
    nev = std::min({2 * nev, at_most, n - 2});
  }
}

// Rows (and columns) of A picked by `rows` and `cols`, each full index -> its index in the block
// or -1.
SparseMatrix block(const SparseMatrix& a, const std::vector<int>& rows, Eigen::Index nrows,
                   const std::vector<int>& cols, Eigen::Index ncols) {
  std::vector<Eigen::Triplet<double, int>> t;
  for (int c = 0; c < a.outerSize(); ++c) {
    if (cols[static_cast<std::size_t>(c)] < 0) continue;
    for (SparseMatrix::InnerIterator it(a, c); it; ++it)
      if (const int r = rows[static_cast<std::size_t>(it.row())]; r >= 0)
        t.emplace_back(r, cols[static_cast<std::size_t>(c)], it.value());
  }
  SparseMatrix b(nrows, ncols);
  b.setFromTriplets(t.begin(), t.end());
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
                           const std::vector<Eigen::Index>& interface, double up_to_hz) {
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

  Cholesky kii_factor(kii);
  if (kii_factor.info() != Eigen::Success)
    throw std::domain_error(
        "the body moves with its interface held still (K_ii is not positive "
        "definite): hold it in the FE tool or add interface nodes");
  const Eigen::MatrixXd psi = -kii_factor.solve(Eigen::MatrixXd(kib));
  const double lambda_max = std::pow(numeric::kTwoPi * up_to_hz, 2);
  const Modes phi = modes_below(kii, mii, lambda_max, ni);

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
  // Symmetric to rounding by construction; made exactly so for the eigen solvers downstream.
  cb.K = 0.5 * (cb.K + cb.K.transpose()).eval();
  cb.M = 0.5 * (cb.M + cb.M.transpose()).eval();
  return cb;
}

}  // namespace flexloop::plant::superelement
