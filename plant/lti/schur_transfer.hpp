// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// C (pI - A)^-1 B on A's complex Schur form, for searches that evaluate a transfer at thousands
// of points (a disk margin's peak on a grid):
//
//   A - sI = U T U^H (T upper triangular, U unitary)
//     =>   C (pI - A)^-1 B = (C U) ((p - s) I - T)^-1 (U^H B),
//
// one triangular back substitution a point (n^2 m / 2 complex products) where the Hessenberg
// method (frequency_response.hpp) first reduces (pI - H) by n - 1 Givens rotations. Backward
// stable as that one (U is unitary): no eigenvector basis, so a Jordan block (a delay chain's
// nilpotent states, double integrators) costs no accuracy. The form is of the balanced A - sI (s:
// the shift, 1 for a discrete loop whose poles crowd near z = 1: their distance to the unit circle
// is then resolved to eps of the shifted matrix; see modal_form.hpp), and the caller passes p - s,
// which it can form without cancellation (e^{jwT} - 1 = -2 sin^2(wT/2) + j sin(wT)).
#include <Eigen/Dense>
#include <complex>

namespace flexloop::plant::lti {

class SchurTransfer {
 public:
  /// @throws std::invalid_argument when the sizes do not close (A square n x n, B n x m,
  /// C p x n) or the Schur form did not converge.
  SchurTransfer(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                double shift);
  /// C (pI - A)^-1 B at p = shift + offset into g; false when it is not finite there (p on or
  /// next to an eigenvalue).
  bool evaluate(std::complex<double> offset, Eigen::MatrixXcd& g) const;
  /// The eigenvalues of A (the shift added back to T's diagonal).
  Eigen::VectorXcd poles() const {
    Eigen::VectorXcd p(tr_.rows());
    p.real() = tr_.diagonal().array() + shift_;
    p.imag() = ti_.diagonal();
    return p;
  }

 private:
  // T, C U and U^H B (balancing folded in), each as its real and imaginary part.
  Eigen::MatrixXd tr_, ti_, cur_, cui_, ubr_, ubi_;
  double shift_;
};

}  // namespace flexloop::plant::lti
