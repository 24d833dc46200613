#pragma once
// The discrete PI force feedback on the general path: any channel count 1 .. kMaxChannels, sized
// at start-up. The same law, start-up checks and gains as the compiled PiController<Scalar, N>
// (pi_controller.hpp has the law; pi_step_gains.hpp the shared start-up), written with Eigen's
// no-alias products into storage sized once:
//
//   f = y - D22 u_{k-1-d},  v = G_f f + s,  u = clamp(v),  s += u - v,  s = a s + b G_x (f + D22 u)
//
// step() never allocates, locks, throws or makes a system call (tests/alloc checks it).
#include <Eigen/Core>
#include <vector>

#include "controller/runtime/pi_parameters.hpp"
#include "controller/runtime/pi_step_gains.hpp"
#include "online/numeric/channel_limits.hpp"

namespace flexloop::controller::runtime {

template <typename Scalar>
class GeneralPiController {
 public:
  using Vector = plant::runtime::BoundedVector<Scalar, plant::runtime::kMaxChannels>;
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

  /// n channels, 1 .. kMaxChannels. @throws std::invalid_argument as pi_step_gains, or for n
  /// outside the range.
  static GeneralPiController from_parameters(const PiParameters& p, Eigen::Index n);

  Eigen::Index channels() const noexcept { return s_.size(); }

  /// One sample: y = the measured forces (any vector expression of channels() entries). Returns
  /// the (saturated) command to hold until the next sample.
  template <typename Y>
  const Vector& step(const Eigen::MatrixBase<Y>& y) noexcept {
    f_ = y;
    subtract_feedthrough(measured_command());
    v_ = s_;
    v_.noalias() += G_f_ * f_;
    u_ = v_.cwiseMax(u_min_).cwiseMin(u_max_);
    s_ += u_ - v_;  // exactly zero while no channel saturates
    subtract_feedthrough(-u_);
    g_.noalias() = G_x_ * f_;
    s_ = a_ * s_ + b_ * g_;
    remember(u_);
    return u_;
  }

  /// Bumpless start: the next step(y_now) returns u_now.
  void start(const Vector& y_now, const Vector& u_now) noexcept {
    for (auto& h : history_) h = u_now;
    f_ = y_now;
    subtract_feedthrough(u_now);
    s_ = u_now;
    s_.noalias() -= G_f_ * f_;
  }
  /// When the actuator reports that it applied something else (e.g. a safe command).
  void set_previous_command(const Vector& u) noexcept { history_[head_] = u; }
  const Vector& previous_command() const noexcept { return history_[head_]; }
  /// The integrator state x = G_x^-1 s (allocates nothing; not used in a step).
  Vector state() const noexcept {
    Vector x(s_.size());
    x.noalias() = G_x_inv_ * s_;
    return x;
  }
  void set_state(const Vector& x) noexcept { s_.noalias() = G_x_ * x; }
  void reset() noexcept {
    s_.setZero();
    for (auto& h : history_) h.setZero();
  }

 private:
  GeneralPiController() = default;

  // f <- f - D22 u (D22 = I: force sensors in series with the actuators).
  template <typename U>
  void subtract_feedthrough(const Eigen::MatrixBase<U>& u) noexcept {
    if (identity_feedthrough_)
      f_ -= u;
    else
      f_.noalias() -= D22_ * u;
  }
  const Vector& measured_command() const noexcept {
    const int i = head_ - delay_;
    return history_[static_cast<std::size_t>(i < 0 ? i + kHistory : i)];
  }
  void remember(const Vector& u) noexcept {
    head_ = head_ + 1 == kHistory ? 0 : head_ + 1;
    history_[static_cast<std::size_t>(head_)] = u;
  }

  static constexpr int kHistory = kMaxFeedthroughDelay + 1;
  Matrix G_f_, G_x_, G_x_inv_, D22_;
  bool identity_feedthrough_ = true;
  Scalar a_ = 1, b_ = 0;
  int delay_ = 0, head_ = 0;
  std::vector<Vector> history_;  // history_[head_]: the last command
  Vector u_min_, u_max_, s_, f_, v_, u_, g_;
};

extern template class GeneralPiController<double>;
extern template class GeneralPiController<float>;

}  // namespace flexloop::controller::runtime
