// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Poles as printed: a pole within round-off of s = 0 is an integrator and is printed as one
// (0 rad/s, "integrator"), never with a frequency and a damping computed from round-off (a pole
// at +9.6e-14 rad/s has "damping -1", meaningless).
//
// The round-off tolerance. poles() (modal_analysis.hpp) balances A and takes the eigenvalues of
// Eigen's real Schur form, a backward-stable method: they are the exact eigenvalues of A + E with
// |E| of order n eps |A_b|, and the balanced |A_b| is of the order of the spectral radius rho. A
// semi-simple eigenvalue at 0 (the PI's integrators, one per strut) therefore comes out at a few
// eps x rho: the metrology frame's six at |s| <= 1.2e-13 rad/s with rho = 62.9 rad/s, 8.7 eps x
// rho (tests/analysis/test_pole_text.cpp). kIntegratorRoundOff = 512 eps (1.1e-13) leaves a
// factor of about 60 above that, and takes no real pole for an integrator unless it is 1e13
// times slower than the fastest one (a 1e-8 Hz leak beside a 100 kHz mode). A defective integrator
// chain (a rigid body's or a floor's double integrator, a Jordan block) is resolved only to about
// sqrt(eps) rho when A is not exactly block-triangular: such poles are then printed as the tiny
// poles they were computed as, with their damping (model_reduction.hpp and discretise.hpp decide
// on those with a sqrt(eps) tolerance of their own).
#include <Eigen/Core>
#include <complex>
#include <string>

#include "numeric/constants.hpp"

namespace flexloop::plant::lti {

/// Relative round-off of a pole at s = 0 (see the header comment).
inline constexpr double kIntegratorRoundOff = 512 * numeric::kEps;

/// kIntegratorRoundOff x the largest |pole| of a system (0 for none): |s| <= this is s = 0.
double integrator_tolerance(const Eigen::VectorXcd& poles);

/// |s| <= tolerance (from integrator_tolerance of the system s belongs to).
bool is_integrator(std::complex<double> s, double tolerance);

/// The damping ratio -Re s / |s| of a pole that is not an integrator; NaN for an integrator
/// (it has none).
double damping_ratio(std::complex<double> s, double tolerance);

/// What an integrator is printed as: "integrator (computed |s| = 3.1e-14 rad/s, round-off)", or
/// "integrator" when s is exactly 0.
std::string integrator_text(std::complex<double> s);

/// One pole as text: "-31.4788 - 54.3777j rad/s (10 Hz, damping 0.501)", or for an integrator
/// "0 rad/s, integrator (computed |s| = 3.1e-14 rad/s, round-off)".
std::string pole_text(std::complex<double> s, double tolerance);

}  // namespace flexloop::plant::lti
