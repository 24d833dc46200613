#include "controller/design/sampled_loop_stability.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "controller/design/loop_stability.hpp"
#include "plant/lti/frequency_response.hpp"

namespace flexloop::controller::design {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("sampled loop: " + what);
}

}  // namespace

Eigen::MatrixXd sampled_loop_matrix(const plant::lti::DiscreteStateSpace& g22, const PiGains& gains,
                                    const SampledLoopHardware& hw) {
  using Eigen::Index;
  using Eigen::MatrixXd;
  const plant::lti::StateSpace& p = g22.sys;
  p.validate();
  const Index m = gains.K_P.rows(), nx = p.nx();
  require(gains.K_P.cols() == m && gains.K_I.rows() == m && gains.K_I.cols() == m,
          "K_P and K_I must be square and of one size");
  require(p.nu() == m && p.ny() == m, "the feedback path has " + std::to_string(p.nu()) +
                                          " inputs and " + std::to_string(p.ny()) +
                                          " outputs, the controller " + std::to_string(m) +
                                          " channels");
  require(std::isfinite(g22.dt) && g22.dt > 0, "the sample time must be finite and > 0");
  require(hw.feedthrough_delay >= 0, "the feedthrough delay must not be negative");
  require(std::isfinite(hw.actuator_gain) && hw.actuator_gain != 0,
          "the actuator gain must be finite and not zero");
  require(std::isfinite(hw.actuator_lag_s) && hw.actuator_lag_s >= 0,
          "the actuator lag must be finite and >= 0");
  require(std::isfinite(hw.sensor_gain_error) && hw.sensor_gain_error > -1,
          "the sensor gain error must be above -1");
  const MatrixXd I = MatrixXd::Identity(m, m);
  const MatrixXd F = hw.removed_feedthrough.size() == 0 ? I : hw.removed_feedthrough;
  require(F.rows() == m && F.cols() == m,
          "the removed feedthrough must be " + std::to_string(m) + "x" + std::to_string(m));

  const double T = g22.dt, wl = gains.settings.leak_rad_s;
  const Eigen::FullPivLU<MatrixXd> loop(I + gains.K_P * F);
  require(loop.isInvertible(), "I + K_P F is singular: the loop is ill-posed");
  const MatrixXd G_f = -loop.solve(gains.K_P), G_x = -loop.solve(gains.K_I);
  const double a = std::exp(-wl * T), b = wl > 0 ? -std::expm1(-wl * T) / wl : T;
  const bool lag = hw.actuator_lag_s > 0;
  const double one_minus_al = lag ? -std::expm1(-T / hw.actuator_lag_s) : 1.0;
  const double al = 1 - one_minus_al, bl = lag ? hw.actuator_lag_s / T * one_minus_al : 0.0;
  const double g = hw.actuator_gain, gain = 1 + hw.sensor_gain_error;

  // Offsets of the state blocks.
  const Index d = hw.feedthrough_delay;
  const Index ix = 0, ih = nx, is = ih + m, iu = is + d * m, ixi = iu + (d + 1) * m, il = ixi + m,
              n = il + (lag ? m : 0);

  // Signals of sample k as rows acting on the loop state.
  MatrixXd s = MatrixXd::Zero(m, n);  // s_k = Cd x + Dd h
  s.middleCols(ix, nx) = p.C;
  s.middleCols(ih, m) = p.D;
  MatrixXd y = MatrixXd::Zero(m, n);  // y_k = (1 + eps) s_{k-d}
  if (d == 0)
    y = gain * s;
  else
    y.middleCols(is + (d - 1) * m, m) = gain * I;
  MatrixXd f = y;  // f_k = y_k - F u_{k-1-d}
  f.middleCols(iu + d * m, m) -= F;
  MatrixXd u = G_f * f;  // u_k = G_f f_k + G_x xi_k
  u.middleCols(ixi, m) += G_x;
  MatrixXd force = (1 - bl) * g * u;  // the force over [k, k+1)
  if (lag) force.middleCols(il, m) += bl * I;

  MatrixXd A = MatrixXd::Zero(n, n);
  A.middleRows(ix, nx) = p.B * force;
  A.block(ix, ix, nx, nx) += p.A;
  A.middleRows(ih, m) = force;
  if (d > 0) {
    A.middleRows(is, m) = s;
    for (Index j = 1; j < d; ++j) A.block(is + j * m, is + (j - 1) * m, m, m) = I;
  }
  A.middleRows(iu, m) = u;
  for (Index j = 1; j <= d; ++j) A.block(iu + j * m, iu + (j - 1) * m, m, m) = I;
  A.middleRows(ixi, m) = b * (f + F * u);
  A.block(ixi, ixi, m, m) += a * I;
  if (lag) {
    A.middleRows(il, m) = one_minus_al * g * u;
    A.block(il, il, m, m) += al * I;
  }
  return A;
}

SampledLoopStability sampled_loop_stability(const plant::lti::DiscreteStateSpace& g22,
                                            const PiGains& gains,
                                            const SampledLoopHardware& hardware) {
  const Eigen::MatrixXd A = sampled_loop_matrix(g22, gains, hardware);
  SampledLoopStability r;
  // The continuous verdict's tolerance (Re s > kUnstableTolerance w_d) mapped by z = e^{sT}, and
  // never below the rounding of a repeated pole at z = 1 (see the header).
  r.tolerance = std::max(std::expm1(kUnstableTolerance * gains.settings.omega_d_rad_s * g22.dt),
                         kSampledRoundingTolerance);
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

}  // namespace flexloop::controller::design
