// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Offline discretisation of a continuous LTI system  dx/dt = A x + B u,  y = C x + D u  at a
// sample time T (doc/design.md §5). Every result carries its method, T and the spectral radius of
// Ad.
//
// Zero-order hold (u constant over [kT, (k+1)T)), exact:
//   expm([A B; 0 0]·T) = [Ad Bd; 0 I]          Ad = e^{AT},  Bd = ∫0^T e^{As} ds B
//   Cd = C, Dd = D.  No A^-1 anywhere, so singular A (integrators, rigid-body modes) is fine.
//   Both holds balance the augmented matrix by exact powers of two before Eigen's exponential
//   (balanced_exponential.hpp): a stiff plant in SI units has ‖A T‖ ~ ω_max² T, which
//   scaling and squaring alone turns into lost digits (issue 17).
//
// First-order hold (triangle hold: u piecewise linear through the samples u_k), exact:
//   expm([A B 0; 0 0 I/T; 0 0 0]·T) = [Φ Γ1 Γ2; 0 I I; 0 0 I]
//   Φ = e^{AT},  Γ1 = ∫0^T e^{As} ds B,  Γ2 = (1/T) ∫0^T e^{As} (T - s) ds B
//   The continuous state at the samples obeys x_{k+1} = Φ x_k + Γ1 u_k + Γ2 (u_{k+1} - u_k),
//   which is not causal in u. The discrete state is therefore SHIFTED:  ξ_k = x_k - Γ2 u_k
//   (start from ξ_0 = x_0 - Γ2 u_0; with x_0 = 0 and u_0 = 0 simply ξ_0 = 0), giving
//   Ad = Φ,  Bd = Γ1 + (Φ - I) Γ2,  Cd = C,  Dd = D + C Γ2,
//   and y_k = Cd ξ_k + Dd u_k equals the continuous output at t = kT for that input.
//
// Tustin (bilinear), z = (1 + α s)/(1 - α s) with α = T/2, or with pre-warping at ω0 = 2π f0,
//   α = tan(ω0 T/2)/ω0 so that H_d(e^{jω0 T}) = H_c(jω0) exactly. Balanced (sqrt-scaled) form:
//   M = (I - αA)^-1,  Ad = M (I + αA),  Bd = sqrt(2α) M B,  Cd = sqrt(2α) C M,
//   Dd = D + α C M B,   so  H_d(z) = H_c((1/α)(z - 1)/(z + 1)) for every z. The state is a
//   scaled, not the physical, state. M is applied by LU solves, never formed.
//
// Forward Euler (comparison only): Ad = I + AT, Bd = BT, Cd = C, Dd = D;  H_d(z) = H_c((z-1)/T).
//
// Backward Euler (comparison only): x_{k+1} = x_k + T (A x_{k+1} + B u_{k+1}), M = (I - AT)^-1.
//   Like FOH the recursion uses u_{k+1}, so the state is shifted:  ξ_k = x_k - T M B u_k,
//   Ad = M,  Bd = T M^2 B,  Cd = C,  Dd = D + T C M B;   H_d(z) = H_c((z - 1)/(z T)).
//
// Stability guard: if the continuous A is stable or marginally stable (max Re λ <= 0, up to the
// round-off of defective eigenvalues, ~sqrt(eps ||A||)) and the discrete spectral radius exceeds
// 1 + 1e-9, discretise() throws std::invalid_argument naming the method, the offending continuous
// eigenvalue (frequency, damping), T and what would work, unless DiscretisationOptions::force.
// The culprit is found with the method's exact pole map (map_eigenvalue) applied to the
// continuous eigenvalues, marginal ones put back on the imaginary axis, so rigid-body modes whose
// computed eigenvalues sit at 1 + 1e-6 are not mistaken for instability. In exact arithmetic only
// forward Euler can turn a stable plant unstable; a radius above 1 by more than round-off
// (sqrt(eps) max(1, ||A|| T)) that the pole map does not explain is refused as badly scaled.
#include <Eigen/Dense>
#include <complex>
#include <string>

#include "numeric/discretisation_method.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

/// The methods' one enum (numeric/discretisation_method.hpp), which the loop artefact records.
using numeric::DiscretisationMethod;

/// "zoh", "foh", "tustin", "euler", "backward-euler"; throws std::invalid_argument listing them.
DiscretisationMethod parse_discretisation_method(const std::string& name);
std::string to_string(DiscretisationMethod method);

struct DiscretisationOptions {
  DiscretisationMethod method;
  double dt;              ///< sample time [s], > 0
  double prewarp_hz = 0;  ///< Tustin only; 0 = no pre-warping; must be below the Nyquist rate
  bool force = false;     ///< keep a result that turns a stable plant unstable
};

struct DiscreteStateSpace {
  StateSpace sys;  ///< Ad, Bd, Cd, Dd in sys.A .. sys.D, with the continuous system's labels
  double dt;
  DiscretisationMethod method;
  double prewarp_hz;
  double spectral_radius;  ///< max |eig(Ad)|
};

/// Throws std::invalid_argument for an invalid system (see StateSpace::validate), dt <= 0 or not
/// finite, a bad pre-warp frequency, a singular Tustin/backward-Euler solve, or (unless forced) a
/// stable plant made unstable.
DiscreteStateSpace discretise(const StateSpace& c, const DiscretisationOptions& o);

/// The matrix ZOH ([A B; 0 0]·T) or FOH ([A B 0; 0 0 I/T; 0 0 0]·T) exponentiates (balanced,
/// balanced_exponential.hpp); empty for the methods without an exponential.
Eigen::MatrixXd hold_matrix(const StateSpace& c, DiscretisationMethod method, double dt);

/// The induced 1-norm of m (its largest absolute column sum), the norm Eigen's LU rcond() is
/// relative to.
double induced_norm_1(const Eigen::MatrixXd& m);

/// max |λ| over the eigenvalues of a square matrix; 0 for an empty one. Computed on the balanced
/// matrix (balanced_exponential.hpp), so a stiff Ad's radius is right to round-off.
double spectral_radius(const Eigen::MatrixXd& m);

/// Where the method puts a continuous eigenvalue s: e^{sT} (zoh, foh), (1+αs)/(1-αs) (tustin, α as
/// above), 1+sT (euler), 1/(1-sT) (backward-euler). The eigenvalues of Ad are exactly these.
std::complex<double> map_eigenvalue(std::complex<double> s, const DiscretisationOptions& o);

}  // namespace flexloop::plant::lti
