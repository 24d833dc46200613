// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete PI force feedback on the general path: any channel count 1 .. kMaxChannels, sized
// at start-up. The same law, start-up checks and gains as the compiled PiController<Scalar, N>
// (pi_controller.hpp has the law; pi_step_gains.hpp the shared start-up), with the products of
// numeric/dynamic_product.hpp on matrices whose rows are padded to whole SIMD packets, into
// storage sized once:
//
//   f = y - D22 u_{k-1-d},  v = G_f f + s,  u = clamp(v),  s += u - v,  s = a s + b G_x (f + D22 u)
//
// step() never allocates, locks, throws or makes a system call (tests/alloc checks it).
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "artefact/pi_parameters.hpp"
#include "controller/runtime/command_history.hpp"
#include "controller/runtime/loop_controller.hpp"
#include "controller/runtime/pi_step_gains.hpp"
#include "numeric/channel_limits.hpp"
#include "numeric/dynamic_product.hpp"

namespace flexloop::controller::runtime {

template <typename Scalar>
class GeneralPiController {
 public:
  using Vector = numeric::BoundedVector<Scalar, numeric::kMaxChannels>;
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

  /// n channels, 1 .. kMaxChannels. @throws std::invalid_argument as pi_step_gains, or for n
  /// outside the range.
  static GeneralPiController from_parameters(const artefact::PiParameters& p, Eigen::Index n);

  Eigen::Index channels() const noexcept { return u_.size(); }
  Eigen::Index sensors() const noexcept { return u_.size(); }
  Eigen::Index actuators() const noexcept { return u_.size(); }

  /// One sample: y = the measured forces (any vector expression of channels() entries). Returns
  /// the (saturated) command to hold until the next sample.
  template <typename Y>
  const Vector& step(const Eigen::MatrixBase<Y>& y) noexcept {
    // Entry by entry on raw storage: for a handful of channels Eigen's dynamic-size loops (size
    // checks, peeling for alignment) cost more than the arithmetic.
    const Eigen::Index n = u_.size();
    Scalar *f = f_.data(), *u = u_.data(), *s = s_.data();
    numeric::read_entries(y, f);  // entry by entry: see read_entries
    add_feedthrough(history_.measured(delay_), Scalar(-1));
    numeric::product(G_f_.data(), n, f, G_f_.rows(), s, v_.data());  // v = G_f f + s
    const Scalar *v = v_.data(), *lo = u_min_.data(), *hi = u_max_.data();
    for (Eigen::Index i = 0; i < n; ++i) {
      u[i] = std::min(std::max(v[i], lo[i]), hi[i]);
      s[i] += u[i] - v[i];  // exactly zero while no channel saturates
    }
    add_feedthrough(u_, Scalar(1));
    numeric::product(G_x_.data(), n, f, G_x_.rows(), nullptr, g_.data());  // g = G_x f
    const Scalar* g = g_.data();
    for (Eigen::Index i = 0; i < s_.size(); ++i) s[i] = a_ * s[i] + b_ * g[i];
    history_.remember(u_);
    return u_;
  }

  /// Bumpless start: the next step(y_now) returns u_now.
  void start(const Vector& y_now, const Vector& u_now) noexcept {
    history_.fill(u_now);
    f_ = y_now;
    add_feedthrough(u_now, Scalar(-1));
    s_.head(u_.size()) = u_now;
    s_.head(u_.size()).noalias() -= G_f_.topRows(u_.size()) * f_;
  }
  /// The actuator applied u instead of the last answer (a held or safe command): u's force is
  /// what the next measurement contains.
  void set_previous_command(const Vector& u) noexcept { history_.replace_last(u); }
  /// Nothing to report: flexloop's own kernels cannot fail (loop_controller.hpp).
  ControllerReport report() const { return {}; }
  /// The command sent `back` samples before the last (a run's start; 0: the last).
  void set_earlier_command(int back, const Vector& u) noexcept { history_.set_earlier(back, u); }
  const Vector& previous_command() const noexcept { return history_.last(); }
  /// The integrator state x = G_x^-1 s (allocates nothing; not used in a step).
  Vector state() const noexcept {
    Vector x(u_.size());
    x.noalias() = G_x_inv_ * s_.head(u_.size());
    return x;
  }
  void set_state(const Vector& x) noexcept { s_.noalias() = G_x_ * x; }
  void reset() noexcept {
    s_.setZero();
    history_.fill(Vector::Zero(u_.size()));
  }

 private:
  GeneralPiController() = default;

  // f <- f + sign D22 u, sign = ±1 (D22 = I: force sensors in series with the actuators).
  void add_feedthrough(const Vector& u, Scalar sign) noexcept {
    if (identity_feedthrough_) {
      for (Eigen::Index i = 0; i < u.size(); ++i) f_.data()[i] += sign * u.data()[i];
    } else if (sign < 0) {
      f_.noalias() -= D22_ * u;
    } else {
      f_.noalias() += D22_ * u;
    }
  }

  Matrix G_f_, G_x_;  // rows padded to whole SIMD packets (zeros below)
  Matrix G_x_inv_, D22_;
  bool identity_feedthrough_ = true;
  Scalar a_ = 1, b_ = 0;
  int delay_ = 0;
  CommandHistory<Vector> history_;
  Vector u_min_, u_max_, f_, u_;
  // The integral command s and the products' sums v = G_f f + s and g = G_x f, with padded rows
  // (the padding zero), as the products write them.
  Vector s_, v_, g_;
};

extern template class GeneralPiController<double>;
extern template class GeneralPiController<float>;

}  // namespace flexloop::controller::runtime
