// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/discretise.hpp"

#include "plant/lti/balanced_exponential.hpp"
#include "plant/lti/pole_text.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace flexloop::plant::lti {

Eigen::MatrixXd hold_matrix(const StateSpace& c, DiscretisationMethod method, double dt) {
  const Eigen::Index n = c.nx(), m = c.nu();
  if (method == DiscretisationMethod::kZeroOrderHold) {
    Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(n + m, n + m);
    aug.topLeftCorner(n, n) = c.A * dt;
    aug.topRightCorner(n, m) = c.B * dt;
    return aug;
  }
  if (method == DiscretisationMethod::kFirstOrderHold) {
    // [A B 0; 0 0 I/T; 0 0 0]·T: the middle block is the input, the last its slope over the step.
    Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(n + 2 * m, n + 2 * m);
    aug.block(0, 0, n, n) = c.A * dt;
    aug.block(0, n, n, m) = c.B * dt;
    aug.block(n, n + m, m, m).setIdentity();
    return aug;
  }
  return {};
}

namespace {

using Eigen::Index;
using Eigen::MatrixXd;

constexpr double kGrowthTolerance = 1e-9;  // spectral radius above 1 + this counts as unstable

struct MethodName {
  DiscretisationMethod method;
  const char* name;
};
constexpr MethodName kMethodNames[] = {
    {DiscretisationMethod::kZeroOrderHold, "zoh"},
    {DiscretisationMethod::kFirstOrderHold, "foh"},
    {DiscretisationMethod::kTustin, "tustin"},
    {DiscretisationMethod::kForwardEuler, "euler"},
    {DiscretisationMethod::kBackwardEuler, "backward-euler"},
};

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Of the balanced matrix (balanced_exponential.hpp), which has the same eigenvalues: unbalanced,
// a stiff A or Ad (entries from ω_max² down to 1) gets them wrong far beyond round-off, e.g. a
// spectral radius of 1.0001 for an undamped 20-element cantilever at 1 kHz.
Eigen::VectorXcd eigenvalues(const MatrixXd& m) {
  if (m.rows() == 0) return {};
  Eigen::EigenSolver<MatrixXd> es(m.allFinite() ? balance(m).balanced : m,
                                  /*computeEigenvectors=*/false);
  if (es.info() != Eigen::Success)
    throw std::runtime_error("eigenvalue computation did not converge");
  return es.eigenvalues();
}

// Tustin's s -> z scale: (1 + αs)/(1 - αs). Pre-warping picks α so that s = jω0 lands on
// z = e^{jω0 T} exactly instead of at the compressed frequency (2/T) atan(ω0 T/2).
double tustin_alpha(const DiscretisationOptions& o) {
  if (o.prewarp_hz == 0) return o.dt / 2;
  const double w0 = 2 * std::numbers::pi * o.prewarp_hz;
  return std::tan(w0 * o.dt / 2) / w0;
}

void check_options(const DiscretisationOptions& o) {
  if (!std::isfinite(o.dt) || o.dt <= 0)
    throw std::invalid_argument("discretise: the sample time must be finite and > 0, is " +
                                fmt("%g", o.dt));
  if (!std::isfinite(o.prewarp_hz) || o.prewarp_hz < 0)
    throw std::invalid_argument("discretise: the pre-warp frequency must be finite and >= 0, is " +
                                fmt("%g", o.prewarp_hz));
  if (o.prewarp_hz > 0 && o.method != DiscretisationMethod::kTustin)
    throw std::invalid_argument("discretise: pre-warping applies to tustin only, not " +
                                to_string(o.method));
  const double nyquist = 0.5 / o.dt;
  if (o.prewarp_hz >= nyquist)
    throw std::invalid_argument("discretise: the pre-warp frequency " + fmt("%g", o.prewarp_hz) +
                                " Hz must be below the Nyquist frequency " + fmt("%g", nyquist) +
                                " Hz");
}

// LU of I - αA, which Tustin and backward Euler must solve with; singular exactly when A has the
// real eigenvalue 1/α, which the message names. "Singular" is judged against the size of the
// terms that make the matrix, 1 + α|A|, not against the matrix itself: near 1/α the difference
// I - αA is pure rounding (its sign and size depend on whether the machine fuses the
// multiply-add), and its own rcond can look perfect (a 1x1 matrix always does).
Eigen::PartialPivLU<MatrixXd> factor(const MatrixXd& A, double alpha, const std::string& method) {
  const MatrixXd m = MatrixXd::Identity(A.rows(), A.cols()) - alpha * A;
  Eigen::PartialPivLU<MatrixXd> lu(m);
  if (m.rows() == 0) return lu;  // no states: nothing to solve
  const double terms = 1.0 + alpha * induced_norm_1(A);
  const double inverse_norm = 1.0 / (lu.rcond() * induced_norm_1(m));  // estimate of |m^-1|_1
  const double pole = 1 / alpha;
  if (!(inverse_norm * terms * m.rows() * std::numeric_limits<double>::epsilon() < 1))
    throw std::invalid_argument("discretise: " + method +
                                " is singular at this rate: A has an eigenvalue at (or very "
                                "near) " +
                                fmt("%.6g", pole) + " rad/s; change the rate or use zoh");
  return lu;
}

void zero_order_hold(const StateSpace& c, double dt, StateSpace& d) {
  const Index n = c.nx(), m = c.nu();
  const MatrixXd e = balanced_exponential(hold_matrix(c, DiscretisationMethod::kZeroOrderHold, dt));
  d.A = e.topLeftCorner(n, n);
  d.B = e.topRightCorner(n, m);
  d.C = c.C;
  d.D = c.D;
}

void first_order_hold(const StateSpace& c, double dt, StateSpace& d) {
  const Index n = c.nx(), m = c.nu();
  const MatrixXd e =
      balanced_exponential(hold_matrix(c, DiscretisationMethod::kFirstOrderHold, dt));
  const MatrixXd phi = e.block(0, 0, n, n);
  const MatrixXd g1 = e.block(0, n, n, m);
  const MatrixXd g2 = e.block(0, n + m, n, m);
  // Shifted state ξ = x - Γ2 u removes the dependence on u_{k+1} (see the header).
  d.A = phi;
  d.B = g1 + (phi - MatrixXd::Identity(n, n)) * g2;
  d.C = c.C;
  d.D = c.D + c.C * g2;
}

void tustin(const StateSpace& c, double alpha, StateSpace& d) {
  const Index n = c.nx();
  const MatrixXd eye = MatrixXd::Identity(n, n);
  const auto lu = factor(c.A, alpha, "tustin");
  const MatrixXd mb = lu.solve(c.B);
  // C M = (M^T C^T)^T: a solve with the transposed matrix, not an inverse.
  const auto lut = factor(c.A.transpose(), alpha, "tustin");
  const MatrixXd cm = lut.solve(c.C.transpose()).transpose();
  const double root = std::sqrt(2 * alpha);
  d.A = lu.solve(eye + alpha * c.A);
  d.B = root * mb;
  d.C = root * cm;
  d.D = c.D + alpha * (c.C * mb);
}

void forward_euler(const StateSpace& c, double dt, StateSpace& d) {
  d.A = MatrixXd::Identity(c.nx(), c.nx()) + dt * c.A;
  d.B = dt * c.B;
  d.C = c.C;
  d.D = c.D;
}

void backward_euler(const StateSpace& c, double dt, StateSpace& d) {
  const Index n = c.nx();
  const MatrixXd eye = MatrixXd::Identity(n, n);
  const auto lu = factor(c.A, dt, "backward-euler");
  const MatrixXd mb = lu.solve(c.B);
  // Shifted state ξ = x - T M B u (see the header).
  d.A = lu.solve(eye);
  d.B = dt * lu.solve(mb);
  d.C = c.C;
  d.D = c.D + dt * (c.C * mb);
}

// Why a stable plant became unstable and what would work instead. `lambda` holds the continuous
// eigenvalues with marginal ones already put on the imaginary axis; `tol` is the round-off scale.
std::string refusal(const Eigen::VectorXcd& lambda, const DiscretisationOptions& o, double rho,
                    double tol) {
  Index worst = 0;
  for (Index i = 1; i < lambda.size(); ++i)
    if (std::abs(map_eigenvalue(lambda(i), o)) > std::abs(map_eigenvalue(lambda(worst), o)))
      worst = i;
  const double rate = 1 / o.dt;
  std::string msg = "discretise: " + to_string(o.method) + " at dt = " + fmt("%.6g", o.dt) +
                    " s (" + fmt("%.6g", rate) + " Hz) maps the stable continuous eigenvalue " +
                    pole_text(lambda(worst), integrator_tolerance(lambda)) +
                    " to |z| = " + fmt("%.6g", std::abs(map_eigenvalue(lambda(worst), o))) +
                    " (spectral radius " + fmt("%.6g", rho) +
                    " > 1), so the discrete plant would be unstable. ";
  if (o.method == DiscretisationMethod::kForwardEuler) {
    // |1 + λT| <= 1  <=>  T <= -2 Re λ / |λ|^2, i.e. a rate above |λ|^2 / (-2 Re λ) = ωn / (2ζ).
    double needed = 0;
    bool possible = true;
    for (const auto& s : lambda) {
      if (std::abs(s) <= tol) continue;  // integrators map to z = 1 at any rate
      if (s.real() >= 0) {
        possible = false;
        continue;
      }
      needed = std::max(needed, std::norm(s) / (-2 * s.real()));
    }
    msg += "Use zoh, foh or tustin (stable at any rate for a stable plant) or backward-euler";
    if (possible)
      msg += ", or a rate above " + fmt("%.6g", needed) + " Hz for euler";
    else
      msg += "; no rate makes euler stable for an undamped mode";
  } else {
    msg +=
        "This method preserves stability in exact arithmetic; use zoh or tustin, or another rate";
  }
  return msg + " (--force keeps the unstable result).";
}

// Refuses (std::invalid_argument) a result that turns a stable continuous plant unstable.
// Defective marginal eigenvalues (rigid-body modes: Jordan blocks at 0) are computed only to about
// sqrt(eps ||A||), for A and for Ad alike, so the decision is made on the method's exact pole map
// applied to the continuous eigenvalues with marginal ones put back on the imaginary axis; the
// numerical spectral radius of Ad must also exceed 1 + 1e-9. A result whose radius exceeds 1 by
// more than round-off although the pole map says it should not is refused too (badly scaled A).
void stability_guard(const StateSpace& c, const DiscretisationOptions& o, double rho) {
  if (o.force || rho <= 1 + kGrowthTolerance || c.nx() == 0) return;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double norm = c.A.norm();
  const double tol = 10 * std::sqrt(eps * std::max(1.0, norm));
  Eigen::VectorXcd lambda = eigenvalues(c.A);
  if (lambda.real().maxCoeff() > tol) return;  // unstable plant: its discrete form is too
  for (auto& s : lambda) s = {std::min(s.real(), 0.0), s.imag()};
  double predicted = 0;
  for (const auto& s : lambda) predicted = std::max(predicted, std::abs(map_eigenvalue(s, o)));
  if (predicted > 1 + kGrowthTolerance) throw std::invalid_argument(refusal(lambda, o, rho, tol));
  const double allowance = std::sqrt(eps) * std::max(1.0, norm * o.dt);
  if (rho > 1 + allowance)
    throw std::invalid_argument(
        "discretise: " + to_string(o.method) + " at dt = " + fmt("%.6g", o.dt) +
        " s gives spectral radius " + fmt("%.9g", rho) +
        " for a stable plant although the method maps its eigenvalues to at most |z| = " +
        fmt("%.9g", predicted) + ": round-off dominates (||A|| dt = " + fmt("%.3g", norm * o.dt) +
        "). Rescale the states or use a higher rate (--force keeps the result).");
}

}  // namespace

DiscretisationMethod parse_discretisation_method(const std::string& name) {
  std::string valid;
  for (const auto& [method, text] : kMethodNames) {
    if (name == text) return method;
    valid += (valid.empty() ? "" : ", ") + std::string(text);
  }
  throw std::invalid_argument("unknown discretisation method '" + name + "'; valid: " + valid);
}

std::string to_string(DiscretisationMethod method) {
  for (const auto& [m, text] : kMethodNames)
    if (m == method) return text;
  throw std::invalid_argument("invalid DiscretisationMethod value");
}

double induced_norm_1(const Eigen::MatrixXd& m) {
  return m.size() == 0 ? 0.0 : m.cwiseAbs().colwise().sum().maxCoeff();
}

double spectral_radius(const Eigen::MatrixXd& m) {
  if (m.rows() != m.cols()) throw std::invalid_argument("spectral_radius: matrix is not square");
  const auto lambda = eigenvalues(m);
  return lambda.size() == 0 ? 0.0 : lambda.cwiseAbs().maxCoeff();
}

std::complex<double> map_eigenvalue(std::complex<double> s, const DiscretisationOptions& o) {
  switch (o.method) {
    case DiscretisationMethod::kZeroOrderHold:
    case DiscretisationMethod::kFirstOrderHold:
      return std::exp(s * o.dt);
    case DiscretisationMethod::kTustin: {
      const double a = tustin_alpha(o);
      return (1.0 + a * s) / (1.0 - a * s);
    }
    case DiscretisationMethod::kForwardEuler:
      return 1.0 + s * o.dt;
    case DiscretisationMethod::kBackwardEuler:
      return 1.0 / (1.0 - s * o.dt);
  }
  throw std::invalid_argument("invalid DiscretisationMethod value");
}

DiscreteStateSpace discretise(const StateSpace& c, const DiscretisationOptions& o) {
  c.validate();
  check_options(o);

  DiscreteStateSpace d{
      .sys = {}, .dt = o.dt, .method = o.method, .prewarp_hz = o.prewarp_hz, .spectral_radius = 0};
  d.sys.states = c.states;
  d.sys.inputs = c.inputs;
  d.sys.outputs = c.outputs;
  switch (o.method) {
    case DiscretisationMethod::kZeroOrderHold:
      zero_order_hold(c, o.dt, d.sys);
      break;
    case DiscretisationMethod::kFirstOrderHold:
      first_order_hold(c, o.dt, d.sys);
      break;
    case DiscretisationMethod::kTustin:
      tustin(c, tustin_alpha(o), d.sys);
      break;
    case DiscretisationMethod::kForwardEuler:
      forward_euler(c, o.dt, d.sys);
      break;
    case DiscretisationMethod::kBackwardEuler:
      backward_euler(c, o.dt, d.sys);
      break;
  }
  if (!(d.sys.A.allFinite() && d.sys.B.allFinite() && d.sys.C.allFinite() && d.sys.D.allFinite()))
    throw std::invalid_argument("discretise: " + to_string(o.method) +
                                " at dt = " + fmt("%g", o.dt) +
                                " s overflowed (the plant grows too fast over one sample); use a "
                                "higher rate");
  d.spectral_radius = spectral_radius(d.sys.A);

  stability_guard(c, o, d.spectral_radius);
  return d;
}

}  // namespace flexloop::plant::lti
