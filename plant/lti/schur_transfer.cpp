#include "plant/lti/schur_transfer.hpp"

#include <stdexcept>

#include "plant/lti/frequency_response.hpp"

namespace flexloop::plant::lti {

SchurTransfer::SchurTransfer(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                             const Eigen::MatrixXd& C, double shift)
    : shift_(shift) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n || B.rows() != n || C.cols() != n)
    throw std::invalid_argument("Schur transfer: the sizes of A, B and C do not close");
  // Balanced A - sI: T_b^-1 (A - sI) T_b with exact power-of-two T_b.
  Eigen::MatrixXd shifted = A;
  shifted.diagonal().array() -= shift;
  const Eigen::VectorXd t = balancing_scaling(shifted);
  const Eigen::MatrixXcd balanced =
      (t.cwiseInverse().asDiagonal() * shifted * t.asDiagonal()).cast<std::complex<double>>();
  const Eigen::ComplexSchur<Eigen::MatrixXcd> schur(balanced);
  if (schur.info() != Eigen::Success)
    throw std::invalid_argument("Schur transfer: the Schur form did not converge");
  t_ = schur.matrixT();
  const Eigen::MatrixXcd& U = schur.matrixU();
  cu_ = (C * t.asDiagonal()).cast<std::complex<double>>() * U;
  ub_ = U.adjoint() * (t.cwiseInverse().asDiagonal() * B).cast<std::complex<double>>();
}

bool SchurTransfer::evaluate(std::complex<double> offset, Eigen::MatrixXcd& g) const {
  // ((p - s) I - T) X = U^H B by columns of T from the last: X's row j is final once the rows
  // below it have added their share T(0:j, j) X(j, :) to the rows above. In real arithmetic on
  // the interleaved parts (std::complex's product checks for NaN at each call): a point costs
  // n^2 m / 2 complex products, and this loop is where a disk margin spends its time.
  const Eigen::Index n = t_.rows(), m = ub_.cols();
  Eigen::MatrixXcd x = ub_;
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    const std::complex<double> pivot = offset - t_(j, j);
    const double size = std::norm(pivot);
    if (!(size > 0)) return false;
    const double inv_re = pivot.real() / size, inv_im = -pivot.imag() / size;
    const double* column = reinterpret_cast<const double*>(t_.data() + j * n);
    for (Eigen::Index c = 0; c < m; ++c) {
      double* xc = reinterpret_cast<double*>(x.data() + c * n);
      const double re = xc[2 * j] * inv_re - xc[2 * j + 1] * inv_im;
      const double im = xc[2 * j] * inv_im + xc[2 * j + 1] * inv_re;
      xc[2 * j] = re;
      xc[2 * j + 1] = im;
      for (Eigen::Index i = 0; i < j; ++i) {
        xc[2 * i] += column[2 * i] * re - column[2 * i + 1] * im;
        xc[2 * i + 1] += column[2 * i] * im + column[2 * i + 1] * re;
      }
    }
  }
  g.noalias() = cu_ * x;
  return g.allFinite();
}

}  // namespace flexloop::plant::lti
