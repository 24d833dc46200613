// SPDX-License-Identifier: BSD-3-Clause
#include "controller/design/sampled_loop_stability.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "controller/design/loop_stability.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/solve_or_empty.hpp"

namespace flexloop::controller::design {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("sampled loop: " + what);
}

}  // namespace

SampledLoopModel sampled_loop_model(const plant::lti::DiscreteStateSpace& g22,
                                    const plant::lti::DiscreteStateSpace& controller,
                                    const SampledLoopHardware& hw) {
  using Eigen::Index;
  using Eigen::MatrixXd;
  const plant::lti::StateSpace& p = g22.sys;
  const plant::lti::StateSpace& c = controller.sys;
  p.validate();
  c.validate();
  const Index ns = c.nu(), nc = c.ny(), nxc = c.nx(), nx = p.nx();
  require(p.nu() == nc && p.ny() == ns, "the feedback path has " + std::to_string(p.nu()) +
                                            " inputs and " + std::to_string(p.ny()) +
                                            " outputs, the controller " + std::to_string(ns) +
                                            " inputs and " + std::to_string(nc) + " outputs");
  require(std::isfinite(g22.dt) && g22.dt > 0, "the sample time must be finite and > 0");
  require(std::abs(controller.dt - g22.dt) <= 1e-12 * g22.dt,
          "the controller's sample time differs from the feedback path's");
  require(hw.feedthrough_delay >= 0, "the feedthrough delay must not be negative");
  require(std::isfinite(hw.actuator_gain) && hw.actuator_gain != 0,
          "the actuator gain must be finite and not zero");
  require(std::isfinite(hw.actuator_lag_s) && hw.actuator_lag_s >= 0,
          "the actuator lag must be finite and >= 0");
  require(std::isfinite(hw.sensor_gain_error) && hw.sensor_gain_error > -1,
          "the sensor gain error must be above -1");
  const MatrixXd Is = MatrixXd::Identity(ns, ns), Ic = MatrixXd::Identity(nc, nc);
  require(hw.removed_feedthrough.size() > 0 || ns == nc,
          "an empty removed feedthrough means the identity, which needs as many sensors as "
          "actuators");
  const MatrixXd F = hw.removed_feedthrough.size() == 0 ? Ic : hw.removed_feedthrough;
  require(F.rows() == ns && F.cols() == nc,
          "the removed feedthrough must be " + std::to_string(ns) + "x" + std::to_string(nc));

  const double T = g22.dt;
  const Eigen::FullPivLU<MatrixXd> loop(Ic - c.D * F);
  require(loop.isInvertible(), "I - Dc F is singular: the loop is ill-posed");
  const MatrixXd u_from_f = plant::lti::solve_or_empty(loop, c.D),
                 u_from_xc = plant::lti::solve_or_empty(loop, c.C);
  const bool lag = hw.actuator_lag_s > 0;
  const double one_minus_al = lag ? -std::expm1(-T / hw.actuator_lag_s) : 1.0;
  const double al = 1 - one_minus_al, bl = lag ? hw.actuator_lag_s / T * one_minus_al : 0.0;
  const double g = hw.actuator_gain, gain = 1 + hw.sensor_gain_error;

  // Offsets of the state blocks.
  const Index d = hw.feedthrough_delay;
  const Index ix = 0, ih = nx, is = ih + nc, iu = is + d * ns, ixc = iu + (d + 1) * nc,
              il = ixc + nxc, n = il + (lag ? nc : 0);

  // Signals of sample k as rows acting on the loop state.
  MatrixXd s = MatrixXd::Zero(ns, n);  // s_k = Cd x + Dd h
  s.middleCols(ix, nx) = p.C;
  s.middleCols(ih, nc) = p.D;
  MatrixXd y = MatrixXd::Zero(ns, n);  // y_k = (1 + eps) s_{k-d}
  if (d == 0)
    y = gain * s;
  else
    y.middleCols(is + (d - 1) * ns, ns) = gain * Is;
  MatrixXd f = y;  // f_k = y_k - F u_{k-1-d}
  f.middleCols(iu + d * nc, nc) -= F;
  MatrixXd u = u_from_f * f;  // u_k = E (Cc xc_k + Dc f_k)
  u.middleCols(ixc, nxc) += u_from_xc;
  MatrixXd force = (1 - bl) * g * u;  // the force over [k, k+1)
  if (lag) force.middleCols(il, nc) += bl * Ic;

  MatrixXd A = MatrixXd::Zero(n, n);
  A.middleRows(ix, nx) = p.B * force;
  A.block(ix, ix, nx, nx) += p.A;
  A.middleRows(ih, nc) = force;
  if (d > 0) {
    A.middleRows(is, ns) = s;
    for (Index j = 1; j < d; ++j) A.block(is + j * ns, is + (j - 1) * ns, ns, ns) = Is;
  }
  A.middleRows(iu, nc) = u;
  for (Index j = 1; j <= d; ++j) A.block(iu + j * nc, iu + (j - 1) * nc, nc, nc) = Ic;
  A.middleRows(ixc, nxc) = c.B * (f + F * u);  // xc_{k+1} = Ac xc + Bc (f_k + F u_k)
  A.block(ixc, ixc, nxc, nxc) += c.A;
  if (lag) {
    A.middleRows(il, nc) = one_minus_al * g * u;
    A.block(il, il, nc, nc) += al * Ic;
  }

  // e_k added to u_k on its way to the actuator only: it enters where the force does.
  MatrixXd E = MatrixXd::Zero(n, nc);
  E.middleRows(ix, nx) = (1 - bl) * g * p.B;
  E.middleRows(ih, nc) = (1 - bl) * g * Ic;
  if (lag) E.middleRows(il, nc) = one_minus_al * g * Ic;
  return {std::move(A), std::move(E), std::move(u), T};
}

Eigen::MatrixXd sampled_loop_matrix(const plant::lti::DiscreteStateSpace& g22,
                                    const plant::lti::DiscreteStateSpace& controller,
                                    const SampledLoopHardware& hw) {
  return sampled_loop_model(g22, controller, hw).A;
}

plant::lti::DiscreteStateSpace pi_discrete_controller(const PiGains& gains, double dt) {
  require(gains.K_P.rows() == gains.K_P.cols() && gains.K_I.rows() == gains.K_P.rows() &&
              gains.K_I.cols() == gains.K_P.rows(),
          "K_P and K_I must be square and of one size");
  require(std::isfinite(dt) && dt > 0, "the sample time must be finite and > 0");
  const Eigen::Index m = gains.K_P.rows();
  const double wl = gains.settings.leak_rad_s;
  const double a = std::exp(-wl * dt), b = wl > 0 ? -std::expm1(-wl * dt) / wl : dt;
  plant::lti::DiscreteStateSpace c{{}, dt, plant::lti::DiscretisationMethod::kZeroOrderHold, 0, a};
  c.sys.A = a * Eigen::MatrixXd::Identity(m, m);
  c.sys.B = b * Eigen::MatrixXd::Identity(m, m);
  c.sys.C = -gains.K_I;
  c.sys.D = -gains.K_P;
  for (Eigen::Index i = 0; i < m; ++i) {
    c.sys.states.push_back("xi" + std::to_string(i + 1));
    c.sys.inputs.push_back("sensor " + std::to_string(i + 1));
    c.sys.outputs.push_back("actuator " + std::to_string(i + 1));
  }
  return c;
}

Eigen::MatrixXd sampled_loop_matrix(const plant::lti::DiscreteStateSpace& g22, const PiGains& gains,
                                    const SampledLoopHardware& hw) {
  return sampled_loop_matrix(g22, pi_discrete_controller(gains, g22.dt), hw);
}

namespace {

SampledLoopStability judge(const Eigen::MatrixXd& A, double tolerance) {
  SampledLoopStability r;
  r.tolerance = tolerance;
  if (!A.allFinite()) throw std::invalid_argument("sampled loop: a matrix entry is not finite");
  if (A.rows() == 0) return r;
  const Eigen::VectorXd t = plant::lti::balancing_scaling(A);
  const Eigen::MatrixXd Ab = t.cwiseInverse().asDiagonal() * A * t.asDiagonal();
  const Eigen::EigenSolver<Eigen::MatrixXd> es(Ab, false);
  if (es.info() != Eigen::Success)
    throw std::runtime_error("sampled loop: the eigenvalues did not converge");
  r.poles = es.eigenvalues();
  for (const auto& z : r.poles) {
    const double radius = std::abs(z);
    r.spectral_radius = std::max(r.spectral_radius, radius);
    if (radius > 1 + r.tolerance)
      ++r.unstable;
    else if (radius >= 1 - r.tolerance)
      ++r.marginal;
    else
      r.largest_inner_radius = std::max(r.largest_inner_radius, radius);
  }
  return r;
}

// The continuous verdict's tolerance (Re s > kUnstableTolerance w) mapped by z = e^{sT}, and
// never below the rounding of a repeated pole at z = 1 (see the header).
double unit_circle_tolerance(double reference_rad_s, double dt) {
  return std::max(std::expm1(kUnstableTolerance * reference_rad_s * dt), kSampledRoundingTolerance);
}

}  // namespace

SampledLoopStability sampled_loop_stability(const plant::lti::DiscreteStateSpace& g22,
                                            const PiGains& gains,
                                            const SampledLoopHardware& hardware) {
  return judge(sampled_loop_matrix(g22, gains, hardware),
               unit_circle_tolerance(gains.settings.omega_d_rad_s, g22.dt));
}

SampledLoopStability sampled_loop_stability(const plant::lti::DiscreteStateSpace& g22,
                                            const plant::lti::DiscreteStateSpace& controller,
                                            const SampledLoopHardware& hardware,
                                            double reference_rad_s) {
  return judge(sampled_loop_matrix(g22, controller, hardware),
               unit_circle_tolerance(reference_rad_s, g22.dt));
}

}  // namespace flexloop::controller::design
