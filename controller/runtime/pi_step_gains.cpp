// SPDX-License-Identifier: BSD-3-Clause
#include "controller/runtime/pi_step_gains.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

#include "controller/runtime/command_limits.hpp"

namespace flexloop::controller::runtime {

namespace {

void require(bool ok, const std::string& who, const std::string& what) {
  if (!ok) throw std::invalid_argument(who + ": " + what);
}

const Eigen::MatrixXd& square(const Eigen::MatrixXd& m, Eigen::Index n, const std::string& who,
                              const char* name) {
  require(m.rows() == n && m.cols() == n, who,
          std::string(name) + " is " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
              ", expected " + std::to_string(n) + "x" + std::to_string(n));
  require(m.allFinite(), who, std::string(name) + " has an entry that is not finite");
  return m;
}

}  // namespace

PiStepGains pi_step_gains(const artefact::PiParameters& p, Eigen::Index n, const std::string& who) {
  using M = Eigen::MatrixXd;
  const M& K_P = square(p.K_P, n, who, "K_P");
  const M& K_I = square(p.K_I, n, who, "K_I");
  const M I = M::Identity(n, n);
  const M D22 = p.feedthrough.size() == 0 ? I : square(p.feedthrough, n, who, "feedthrough");
  require(std::isfinite(p.dt) && p.dt > 0, who,
          "dt must be finite and > 0, got " + std::to_string(p.dt));
  require(std::isfinite(p.leak_rad_s) && p.leak_rad_s >= 0, who,
          "leak_rad_s must be finite and >= 0, got " + std::to_string(p.leak_rad_s));
  PiStepGains g;
  const CommandLimits limits = command_limits(p.u_min, p.u_max, n, who);
  g.u_min = limits.u_min;
  g.u_max = limits.u_max;

  const Eigen::FullPivLU<M> loop(I + K_P * D22);
  require(loop.isInvertible(), who,
          "I + K_P D22 is singular: the loop through the sensors' feedthrough is ill-posed");
  const Eigen::FullPivLU<M> integral(K_I);
  require(integral.isInvertible(), who,
          "K_I is singular; anti-windup and bumpless start need it invertible");
  require(p.feedthrough_delay >= 0 && p.feedthrough_delay <= artefact::kMaxFeedthroughDelay, who,
          "feedthrough_delay must be 0 .. " + std::to_string(artefact::kMaxFeedthroughDelay) +
              ", got " + std::to_string(p.feedthrough_delay));
  g.G_f = -loop.solve(K_P);
  g.G_x = -loop.solve(K_I);
  g.G_x_inv = -integral.solve(I + K_P * D22);
  g.D22 = D22;
  g.identity_feedthrough = D22 == I;
  g.delay = p.feedthrough_delay;
  g.a = std::exp(-p.leak_rad_s * p.dt);
  g.b = p.leak_rad_s > 0 ? -std::expm1(-p.leak_rad_s * p.dt) / p.leak_rad_s : p.dt;
  return g;
}

}  // namespace flexloop::controller::runtime
