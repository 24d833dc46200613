// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The matrix exponential of the augmented matrices of ZOH and FOH (discretise.hpp), made
// accurate for stiff plants by balancing first.
//
// Why: a linearised mechanical model in SI units has A = [0 I; -M⁻¹K -M⁻¹C], so ‖A‖ is of
// order ω_max² while its spectral radius is ω_max. Scaling and squaring (Eigen's Padé exponential)
// picks the number of squarings from ‖A T‖ and its rounding errors grow with it: on such
// non-normal matrices the result can be wrong in the leading digits (Ad off by 42 %, 57 % in
// one column, for a 20-element steel cantilever with small rotary inertia at 1 kHz, ‖A T‖ ~ 9e10;
// test_stiff_exponential.cpp).
//
// What: a diagonal similarity D⁻¹ M D with D = diag(2^e) (Parlett-Reinsch balancing, as in
// LAPACK's gebal, without permutations) has the same exponential up to the same similarity,
//   e^M = D e^{D⁻¹ M D} D⁻¹,
// and for such A a norm of order ω_max T instead of ω_max² T. The factors are powers of two, so
// scaling and unscaling round nothing (barring underflow, which the exponent limit keeps away
// from realistic data). The exponential itself stays Eigen's. discretise.cpp balances before its
// eigenvalue computations too (spectral radius of Ad, stability guard), for the same reason.
#include <Eigen/Dense>

namespace flexloop::plant::lti {

struct Balancing {
  Eigen::MatrixXd balanced;   ///< D⁻¹ M D
  Eigen::VectorXi exponents;  ///< D = diag(2^exponents)
};

/// Balances a square matrix: the off-diagonal 1-norms of each row and column made comparable by
/// exact powers of two (Parlett-Reinsch, steps kept only when they shrink the row plus column sum
/// by 5 % or more). An index whose off-diagonal row or column is zero (an input of an augmented
/// matrix) has nothing to balance against and keeps exponent 0; a large B still shrinks, through
/// the rows of the states it feeds.
Balancing balance(const Eigen::MatrixXd& m);

/// e^m computed as D e^{D⁻¹ m D} D⁻¹ with the balancing above and Eigen's exponential.
Eigen::MatrixXd balanced_exponential(const Eigen::MatrixXd& m);

}  // namespace flexloop::plant::lti
