// SPDX-License-Identifier: BSD-3-Clause
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
  const Eigen::MatrixXcd& T = schur.matrixT();
  const Eigen::MatrixXcd& U = schur.matrixU();
  const Eigen::MatrixXcd cu = (C * t.asDiagonal()).cast<std::complex<double>>() * U;
  const Eigen::MatrixXcd ub =
      U.adjoint() * (t.cwiseInverse().asDiagonal() * B).cast<std::complex<double>>();
  tr_ = T.real();
  ti_ = T.imag();
  cur_ = cu.real();
  cui_ = cu.imag();
  ubr_ = ub.real();
  ubi_ = ub.imag();
}

bool SchurTransfer::evaluate(std::complex<double> offset, Eigen::MatrixXcd& g) const {
  // ((p - s) I - T) X = U^H B by columns of T from the last: X's row j is final once the rows
  // below it have added their share T(0:j, j) X(j, :) to the rows above. On the real and
  // imaginary parts apart, so that each update is a real axpy Eigen vectorises: a point costs
  // n^2 m / 2 complex products, and this loop is where a disk margin spends its time.
  const Eigen::Index n = tr_.rows(), m = ubr_.cols();
  Eigen::MatrixXd xr = ubr_, xi = ubi_;
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    const std::complex<double> pivot = offset - std::complex<double>(tr_(j, j), ti_(j, j));
    const double size = std::norm(pivot);
    if (!(size > 0)) return false;
    const std::complex<double> inverse(pivot.real() / size, -pivot.imag() / size);
    const auto t_re = tr_.col(j).head(j), t_im = ti_.col(j).head(j);
    for (Eigen::Index c = 0; c < m; ++c) {
      const std::complex<double> x = std::complex<double>(xr(j, c), xi(j, c)) * inverse;
      xr(j, c) = x.real();
      xi(j, c) = x.imag();
      xr.col(c).head(j) += x.real() * t_re - x.imag() * t_im;
      xi.col(c).head(j) += x.imag() * t_re + x.real() * t_im;
    }
  }
  g.resize(cur_.rows(), m);
  g.real() = cur_ * xr - cui_ * xi;
  g.imag() = cur_ * xi + cui_ * xr;
  return g.allFinite();
}

}  // namespace flexloop::plant::lti
