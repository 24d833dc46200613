// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete state-space controller: a user's own design (MATLAB, Octave, python-control, or
// flexloop's discretisation of a continuous design), of any size, sized at start-up:
//
//   x_{k+1} = A x_k + B y_k,   u_k = C x_k + D y_k        (y: sensors, u: actuator commands)
//
// designed for the discrete plant y_k = C2 x_k + D22 u_k, the usual model in which a sensor sees
// the command of its own sample. In the loop the measurement at sample k holds the command of the
// previous sample (the actuator holds it until the answer arrives): y_k = C2 x_k + D22 u_{k-1-d}
// (d: sensor + transport delay). The controller removes that known feedthrough and solves the
// loop algebraically, exactly as plant::lti::close_loop_sampled models the loop (and as the PI
// force feedback, one case of this law, does):
//
//   f_k = y_k - D22 u_{k-1-d}                  the measurement without the held command
//   v_k = E (C x_k + D f_k),   E = (I - D D22)^-1
//   u_k = clamp(v_k, u_min, u_max)             per channel
//   x_{k+1} = A x_k + B (f_k + D22 u_k)        the measurement with the command actually applied
//
// Without feedthrough (D22 = 0) this is the plain law. Anti-windup (AntiWindup, stated in the
// scene as [controller] anti_windup):
//   "none": the state runs on; it sees the clamp only through D22 u_k.
//   "hold": while any channel is clamped the state holds, x_{k+1} = x_k (conditional
//           integration, as Simulink's clamping for a PID). For a PI-like design this stops the
//           integrators' windup; for an observer-based design (LQG) it stops the estimate too,
//           which resumes where it stood when the clamp releases.
// Neither is a general anti-windup compensator (no Hanus conditioning, no model recovery): a
// design that saturates often should bring its own, e.g. an observer driven by the clamped
// command (feed u back in as a sensor channel).
//
// Bumpless start: start(y_now, u_now) holds u_now and sets x to the least-squares solution of
// C x = (I - D D22) u_now - D f, f = y_now - D22 u_now: the next step(y_now) returns u_now exactly
// when C has full row rank (a state per command at least), the closest command otherwise.
//
// The step is two products over contiguous storage (numeric/dynamic_product.hpp), on rows
// padded to whole SIMD packets:  v = [E C, E D] [x; f],  x+ = [A, B] [x; f] + (B D22) u.
// step() never allocates, locks, throws or makes a system call (tests/alloc checks it).
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "artefact/pi_parameters.hpp"
#include "artefact/state_space_parameters.hpp"
#include "controller/runtime/command_history.hpp"
#include "controller/runtime/loop_controller.hpp"
#include "numeric/channel_limits.hpp"
#include "numeric/dynamic_product.hpp"

namespace flexloop::controller::runtime {

template <typename Scalar>
class StateSpaceController {
 public:
  using Vector = numeric::BoundedVector<Scalar, numeric::kMaxChannels>;
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

  /// @throws std::invalid_argument "StateSpaceController: ..." for sizes that do not close
  /// (sensors and actuators 1 .. kMaxChannels, states 0 .. kMaxControllerStates), non-finite
  /// entries, dt <= 0, limits of the wrong size or with u_min > u_max, a delay outside 0 ..
  /// kMaxFeedthroughDelay, or I - D D22 singular (the loop through the feedthrough is ill-posed).
  static StateSpaceController from_parameters(const artefact::StateSpaceParameters& p);

  Eigen::Index states() const noexcept { return nx_; }
  Eigen::Index sensors() const noexcept { return ns_; }
  Eigen::Index actuators() const noexcept { return u_.size(); }

  /// One sample: y = the sensors (any vector expression of sensors() entries). Returns the
  /// (clamped) command to hold until the next sample.
  template <typename Y>
  const Vector& step(const Eigen::MatrixBase<Y>& y) noexcept {
    const Eigen::Index nc = u_.size();
    Scalar *w = w_.data(), *f = w + nx_, *u = u_.data();
    numeric::read_entries(y, f);
    if (feedthrough_) {  // f = y - D22 u_{k-1-d}
      numeric::product(F_.data(), nc, history_.measured(delay_).data(), F_.rows(), nullptr,
                       fu_.data());
      for (Eigen::Index i = 0; i < ns_; ++i) f[i] -= fu_[i];
    }
    numeric::product(out_.data(), nx_ + ns_, w, out_.rows(), nullptr, v_.data());
    const Scalar *v = v_.data(), *lo = u_min_.data(), *hi = u_max_.data();
    bool clamped = false;
    for (Eigen::Index i = 0; i < nc; ++i) {
      u[i] = std::min(std::max(v[i], lo[i]), hi[i]);
      clamped |= u[i] != v[i];
    }
    if (nx_ > 0 && !(clamped && anti_windup_ == artefact::AntiWindup::kHold)) {
      numeric::product_sum(next_.data(), nx_ + ns_, w, next_u_.data(), nc, u, next_.rows(),
                           static_cast<const Scalar*>(nullptr), x_next_.data());
      std::copy_n(x_next_.data(), nx_, w);
    }
    history_.remember(u_);
    return u_;
  }

  /// Bumpless start (see the header comment).
  void start(const Vector& y_now, const Vector& u_now) noexcept {
    history_.fill(u_now);
    Eigen::Map<Eigen::Matrix<Scalar, Eigen::Dynamic, 1>> x(w_.data(), nx_), f(w_.data() + nx_, ns_);
    f = y_now;
    if (feedthrough_) f.noalias() -= F_.topRows(ns_) * u_now;
    x.noalias() = start_u_ * u_now;
    x.noalias() -= start_f_ * f;
  }
  /// The actuator applied u instead of the last answer (a held or safe command): u's force is
  /// what the next measurement contains.
  void set_previous_command(const Vector& u) noexcept { history_.replace_last(u); }
  /// Nothing to report: flexloop's own kernels cannot fail (loop_controller.hpp).
  ControllerReport report() const { return {}; }
  /// The command sent `back` samples before the last (a run's start; 0: the last).
  void set_earlier_command(int back, const Vector& u) noexcept { history_.set_earlier(back, u); }
  const Vector& previous_command() const noexcept { return history_.last(); }
  /// The controller state x.
  Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>> state() const noexcept {
    return {w_.data(), nx_};
  }
  template <typename X>
  void set_state(const Eigen::MatrixBase<X>& x) noexcept {
    std::copy_n(x.derived().eval().data(), nx_, w_.data());
  }
  void reset() noexcept {
    std::fill_n(w_.data(), nx_, Scalar(0));
    history_.fill(Vector::Zero(u_.size()));
  }

 private:
  StateSpaceController() = default;

  Eigen::Index nx_ = 0, ns_ = 0;
  // Rows padded to whole SIMD packets (zeros below): out_ = [E C, E D], next_ = [A, B],
  // next_u_ = B D22, F_ = D22.
  Matrix out_, next_, next_u_, F_;
  Matrix start_u_, start_f_;  // C^+ (I - D D22), C^+ D: the bumpless start's state
  bool feedthrough_ = false;
  artefact::AntiWindup anti_windup_ = artefact::AntiWindup::kHold;
  int delay_ = 0;
  CommandHistory<Vector> history_;
  // w = [x; f], contiguous: both products read it in place. The products' outputs have padded
  // rows (the padding zero), as the products write them.
  std::vector<Scalar> w_, x_next_, v_, fu_;
  Vector u_min_, u_max_, u_;
};

extern template class StateSpaceController<double>;
extern template class StateSpaceController<float>;

}  // namespace flexloop::controller::runtime
