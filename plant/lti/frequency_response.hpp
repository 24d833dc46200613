// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Frequency response of a continuous-time LTI system, evaluated in state-space form.
//
//   G(jw) = C (jw I - A)^-1 B + D,   w = 2 pi f  [rad/s], f in Hz.
//
// Never forms (jw I - A)^-1 and never a polynomial transfer function (doc/design.md §11). Method
// (Laub, "Efficient multivariable frequency response computations", IEEE TAC 26 (1981)):
//   1. optional balancing: A_b = T^-1 A T with T diagonal, entries powers of two (exact in
//      floating point), so that rows and columns of A have comparable norms; B_b = T^-1 B,
//      C_b = C T. G is unchanged in exact arithmetic; the Hessenberg reduction below is backward
//      stable relative to ||A_b||, which balancing makes small.
//   2. once: A_b = Q H Q^T with H upper Hessenberg and Q orthogonal (Householder,
//      Eigen::HessenbergDecomposition); B_h = Q^T B_b, C_h = C_b Q.
//   3. per frequency: (jw I - H) is upper Hessenberg, so n-1 complex Givens rotations reduce it
//      to upper triangular form R (O(n^2)); the same rotations applied to B_h and one
//      triangular back substitution give X = (jw I - H)^-1 B_h in O(n^2 m); then
//      G = C_h X + D. Total O(n^3) once plus O(n^2 m + p n m) per frequency.
#include <Eigen/Dense>
#include <complex>
#include <vector>

#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

/// `points` frequencies log-spaced from f_min_hz to f_max_hz, both ends included exactly.
/// @throws std::invalid_argument unless 0 < f_min_hz < f_max_hz (finite) and points >= 2.
std::vector<double> log_frequency_grid_hz(double f_min_hz, double f_max_hz, int points);

/// grid_hz (increasing) with each finite resonance frequency inside its range added, in order:
/// a lightly damped peak (0.2 % damping is 0.5 % wide at -3 dB) is then drawn at its height,
/// not cut off between two grid points.
std::vector<double> with_resonances(std::vector<double> grid_hz,
                                    const Eigen::VectorXd& resonances_hz);

/// The phase of g in degrees along the sequence, unwrapped (no jump of more than 180 degrees
/// between neighbours; a fourth-order lag reaches -360), then shifted by whole turns so that the
/// first finite value lies in (-180, 180]. Non-finite entries stay NaN and do not break the
/// unwrapping of the rest.
std::vector<double> unwrapped_phase_deg(const std::vector<std::complex<double>>& g);

struct FrequencyResponseOptions {
  /// Scale A by an exact power-of-two diagonal similarity before the Hessenberg reduction
  /// (no permutations). Harmless when A is already well scaled; helps when state units differ
  /// by many orders of magnitude (positions in m beside forces in N).
  bool balance = true;
};

/// One complex ny x nu matrix G(j 2 pi f) per entry of freqs_hz (any real f, 0 gives the DC
/// gain -C A^-1 B + D).
/// @throws std::invalid_argument when sys.validate() fails or a frequency is not finite.
/// @throws std::domain_error when j 2 pi f is (numerically exactly) an eigenvalue of A, i.e. the
///         response is infinite there; the message names the frequency.
std::vector<Eigen::MatrixXcd> frequency_response(const StateSpace& sys,
                                                 const std::vector<double>& freqs_hz,
                                                 const FrequencyResponseOptions& options = {});

/// The discrete system's response H(z) = Cd (zI - Ad)^-1 Bd + Dd at z = e^{j 2 pi f dt}, by the
/// same Hessenberg method. Same exceptions (a pole on the unit circle at f is infinite).
std::vector<Eigen::MatrixXcd> frequency_response(const DiscreteStateSpace& sys,
                                                 const std::vector<double>& freqs_hz,
                                                 const FrequencyResponseOptions& options = {});

/// C (pI - A)^-1 B + D at arbitrary complex points p, the engine of both frequency responses.
/// @throws std::domain_error when a point is (numerically) an eigenvalue of A.
std::vector<Eigen::MatrixXcd> transfer_at(const StateSpace& sys,
                                          const std::vector<std::complex<double>>& points,
                                          const FrequencyResponseOptions& options = {});

/// C (pI - A)^-1 B + D with A reduced once (steps 1 and 2 above), evaluated one point at a time
/// (step 3): for searches that ask for points one by one (a peak refined by golden section).
/// The numbers are frequency_response's and transfer_at's, which use it.
class TransferFunction {
 public:
  /// @throws std::invalid_argument when sys.validate() fails.
  explicit TransferFunction(const StateSpace& sys, const FrequencyResponseOptions& options = {});
  enum class Point { kFinite, kEigenvalue, kNextToEigenvalue };
  /// G(p) into g; kEigenvalue when p is (numerically exactly) an eigenvalue of A, then
  /// kNextToEigenvalue when G is not finite (g then undefined).
  Point evaluate(std::complex<double> p, Eigen::MatrixXcd& g) const;
  /// G(p). @throws std::domain_error when evaluate does not give kFinite.
  Eigen::MatrixXcd at(std::complex<double> p) const;

 private:
  Eigen::MatrixXcd H_, B_, C_, D_;  // Hessenberg form of the balanced A, Q^T B_b, C_b Q, D
};

/// Singular values of each G: row k holds sigma_1 >= sigma_2 >= ... >= sigma_r of G[k],
/// r = min(ny, nu). Computed by Eigen::BDCSVD (values only).
/// @throws std::invalid_argument when the matrices do not all have the same size.
Eigen::MatrixXd singular_values(const std::vector<Eigen::MatrixXcd>& G);

/// sigma_max(G) as sqrt(lambda_max) of the smaller of G^H G and G G^H (Hermitian eigenvalues
/// only): a fraction of an SVD's cost, and squaring loses nothing at the largest singular value
/// (relative error of order eps there; only the small ones lose digits). 0 for an empty G.
double largest_singular_value(const Eigen::MatrixXcd& G);

/// Exact power-of-two diagonal balancing of a square matrix (LAPACK xGEBAL without
/// permutations): returns the scaling t (A_b = diag(t)^-1 A diag(t)). Exposed for tests and for
/// other state-space algorithms that want the same preconditioning.
Eigen::VectorXd balancing_scaling(const Eigen::MatrixXd& A);

}  // namespace flexloop::plant::lti
