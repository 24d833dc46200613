// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The discrete PI force-feedback controller (doc/design.md §4, §6), the runtime form of
//   σa(s) = -(K_P + K_I / (s + w_l)) σ1(s)                     (controller/design)
// for force sensors in series with the actuators: the measurement y contains the actuator's own
// force, y = (the rest) + D22 u, with D22 = I for the metrology frame. A plain sampled law
// u_k = -(K_P y_k + K_I x_k) would feed its own previous command back with a one-sample delay and
// is unstable once |K_P D22| > 1 (K_P has eigenvalues up to ~23 on the metrology frame). So the
// controller removes its known feedthrough and solves the loop algebraically, as the continuous
// law does. At sample k, with u_{k-1} the command it returned last time (held by the actuator):
//
//   f_k = y_k - D22 u_{k-1-d}                       the force not due to the actuator
//                                                   (d: sensor + transport delay, usually 0)
//   v_k = G_f f_k + G_x x_k,   G_f = -E K_P,  G_x = -E K_I,  E = (I + K_P D22)^-1
//   u_k = clamp(v_k, u_min, u_max)                  per channel
//   x'_k = x_k + G_x^-1 (u_k - v_k)                 anti-windup (zero while unsaturated)
//   x_{k+1} = a x'_k + b (f_k + D22 u_k),   a = e^{-w_l dt},  b = (1 - a)/w_l  (b = dt if w_l = 0)
//
// This is the controller state space (Ac = aI, Bc = bI, Cc = -K_I, Dc = -K_P) closed around D22:
// u = (I - Dc D22)^-1 (Cc x + Dc f),  x+ = Ac x + Bc (f + D22 u), exactly the sampled loop of
// plant::lti::close_loop_sampled (plant/lti/feedback_interconnection.hpp).
//
// The step carries the integral command s = G_x x instead of x (the same law, one product fewer
// and a shorter chain from one sample to the next; x = G_x^-1 s is computed only when asked):
//
//   p_k = G_f f_k,   v_k = p_k + s_k,   u_k = clamp(v_k)
//   s'_k = s_k + (u_k - v_k)                                   (= G_x x'_k)
//   s_{k+1} = a s'_k + b G_x (f_k + D22 u_k)                   (= G_x x_{k+1})
//
// While no channel saturates u_k - v_k is exactly zero, so s'_k = s_k to the last bit.
//
// Anti-windup (back-calculation with a one-sample tracking time): when a channel saturates, the
// integrator state is moved to the one for which the unsaturated law gives the command actually
// applied, G_x x' = u_k - G_f f_k, and integrates from there. This works with coupled (full)
// gains: it changes no unsaturated channel's command at that sample, and the integrator never
// holds more than what the saturated command needs, so on release the command leaves the limit
// continuously. K_I must be invertible (x and s then describe the same controller).
//
// Bumpless start: start(y_now, u_now) sets u_{k-1} = u_now and s = u_now - G_f f with
// f = y_now - D22 u_now, so a first step with y = y_now returns u_now.
//
// step() never allocates, locks, throws or makes a system call. from_parameters (start-up) does.
#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "artefact/pi_parameters.hpp"
#include "controller/runtime/loop_controller.hpp"
#include "controller/runtime/pi_step_gains.hpp"
#include "numeric/column_product.hpp"
#include "numeric/fixed_size_matrix.hpp"

namespace flexloop::controller::runtime {

template <typename Scalar, int N>
class PiController {
  static_assert(N > 0, "the number of channels is compile-time and positive");

 public:
  using Vector = Eigen::Matrix<Scalar, N, 1>;
  using Matrix = Eigen::Matrix<Scalar, N, N>;

  /// @throws std::invalid_argument for gains or feedthrough that are not N x N, non-finite
  /// numbers, dt <= 0, w_l < 0, limits of the wrong size or with u_min > u_max, I + K_P D22
  /// singular (ill-posed loop), or K_I singular (no anti-windup or bumpless start possible).
  static PiController from_parameters(const artefact::PiParameters& p);

  /// One sample: y = measured forces (including the command held since the previous sample),
  /// any vector expression of N entries (read entry by entry: a tail() of the plant's output is
  /// not copied first; for 6 floats Eigen's copy stores and reloads across two stores, which
  /// the store buffer cannot forward). Returns the (saturated) command to hold until the next
  /// sample.
  template <typename Y>
  EIGEN_ALWAYS_INLINE Vector step(const Eigen::MatrixBase<Y>& y) noexcept {
    static_assert(Y::SizeAtCompileTime == N && Y::ColsAtCompileTime == 1,
                  "step: y must be a column vector of N entries");
    if (identity_feedthrough_) {
      // The metrology frame's path. f = y - u_measured is formed once, as N scalars, and both
      // products read it (and f + u) entry by entry: no padded copy of y, which would be written
      // in pieces and read back whole (the store buffer cannot forward that), and no second
      // subtraction (BM_PiStep 13.5-13.7 ns against 15.7-15.9 when each product formed its own
      // y - u_measured). One path for both cases, with D22 u as a returned value, measured 19 ns
      // against 16.
      const Lanes& u_measured = measured_command();
      Scalar f_entries[N];
#pragma GCC unroll 16
      for (int j = 0; j < N; ++j) f_entries[j] = y.coeff(j) - u_measured[j];
      const Eigen::Map<const Vector> f(f_entries);
      const Lanes u = command(numeric::column_product(G_f_, f));
      integrate(numeric::column_product(G_x_, f + u.template head<N>()), u);
      return u.template head<N>();
    }
    Lanes f = pad(y);
    subtract_feedthrough(f, measured_command());
    const Lanes u = command(numeric::column_product(G_f_, f.template head<N>()));
    subtract_feedthrough(f, -u);
    integrate(numeric::column_product(G_x_, f.template head<N>()), u);
    return u.template head<N>();
  }

  static constexpr Eigen::Index channels() noexcept {
    return N;
  }
  static constexpr Eigen::Index sensors() noexcept {
    return N;
  }
  static constexpr Eigen::Index actuators() noexcept {
    return N;
  }

  /// Bumpless start: the next step(y_now) returns u_now. See the header comment.
  void start(const Vector& y_now, const Vector& u_now) noexcept {
    const Lanes u = pad(u_now);
    history_.fill(u);  // the actuator has been holding u_now
    Lanes f = pad(y_now);
    subtract_feedthrough(f, u);
    s_ = u - numeric::column_product(G_f_, f.template head<N>());
  }

  /// The actuator applied u instead of the last answer (a held or safe command): u's force is
  /// what the next measurement contains.
  void set_previous_command(const Vector& u) noexcept {
    history_[head_] = pad(u);
  }
  /// Nothing to report: flexloop's own kernels cannot fail (loop_controller.hpp).
  ControllerReport report() const {
    return {};
  }
  /// The command sent `back` samples before the last (a run's start; 0: the last).
  void set_earlier_command(int back, const Vector& u) noexcept {
    const int i = head_ - back;
    history_[i < 0 ? i + kHistory : i] = pad(u);
  }
  Vector previous_command() const noexcept {
    return history_[head_].template head<N>();
  }
  /// The integrator state x = G_x^-1 s (a product; not used in a step).
  Vector state() const noexcept {
    return G_x_inv_ * s_.template head<N>();
  }
  void set_state(const Vector& x) noexcept {
    s_ = G_x_ * x;
  }
  void reset() noexcept {
    s_.setZero();
    history_.fill(Lanes::Zero());
  }

 private:
  // Vectors padded to whole SIMD packets (numeric/column_product.hpp); the padding lanes
  // stay exactly zero: the padded rows of G_f, G_x and D22 are zero and so are both limits.
  static constexpr int NP = numeric::kPaddedRows<Scalar, N>;
  using Lanes = Eigen::Matrix<Scalar, NP, 1>;
  using LaneMatrix = Eigen::Matrix<Scalar, NP, N>;  // N columns of NP rows

  PiController() = default;

  // The command u = sat(G_f f + s). Only a clamped channel moves the integral command: u - v is
  // exactly zero elsewhere. Branch-free: a data-dependent branch per sample costs more when
  // saturation comes and goes. (Starting the product's sums from s instead of adding s last
  // lengthens the chain from one sample's s to the next: BM_PiStep 13.3 -> 16.8 ns.)
  Lanes command(const Lanes& G_f_f) noexcept {
    const Lanes v = G_f_f + s_;
    const Lanes u = v.cwiseMax(u_min_).cwiseMin(u_max_);
    s_ += u - v;
    return u;
  }
  // s <- a s + b G_x f (f with the new command u fed through), and u remembered as sent.
  void integrate(const Lanes& G_x_f, const Lanes& u) noexcept {
    s_ = a_ * s_ + b_ * G_x_f;
    remember(u);
  }

  template <typename V>
  static Lanes pad(const Eigen::MatrixBase<V>& v) noexcept {
    return numeric::padded_rows<NP>(v);
  }

  // f <- f - D22 u; D22 = I (force sensors in series with the actuators) skips the product.
  void subtract_feedthrough(Lanes& f, const Lanes& u) const noexcept {
    if (identity_feedthrough_)
      f -= u;
    else
      f -= numeric::column_product(D22_, u.template head<N>());
  }

  static constexpr int kHistory = artefact::kMaxFeedthroughDelay + 1;
  // u_{k-1-d}: the command the current measurement contains (d = feedthrough_delay).
  const Lanes& measured_command() const noexcept {
    const int i = head_ - delay_;
    return history_[i < 0 ? i + kHistory : i];
  }
  void remember(const Lanes& u) noexcept {
    head_ = head_ + 1 == kHistory ? 0 : head_ + 1;
    history_[head_] = u;
  }

  LaneMatrix G_f_, G_x_, D22_;
  Matrix G_x_inv_;
  int delay_ = 0, head_ = 0;
  std::array<Lanes, kHistory> history_;  // history_[head_]: the last command
  bool identity_feedthrough_ = true;
  Scalar a_ = 1, b_ = 0;
  Lanes u_min_, u_max_;
  Lanes s_ = Lanes::Zero();  // s = G_x x
};

template <typename Scalar, int N>
PiController<Scalar, N> PiController<Scalar, N>::from_parameters(const artefact::PiParameters& p) {
  using M = Eigen::Matrix<double, N, N>;
  const PiStepGains g = pi_step_gains(p, N, "PiController");
  PiController c;
  c.G_f_ = numeric::padded_rows<NP>(M(g.G_f).template cast<Scalar>());
  c.G_x_ = numeric::padded_rows<NP>(M(g.G_x).template cast<Scalar>());
  c.G_x_inv_ = M(g.G_x_inv).template cast<Scalar>();
  c.D22_ = numeric::padded_rows<NP>(M(g.D22).template cast<Scalar>());
  c.identity_feedthrough_ = g.identity_feedthrough;
  c.delay_ = g.delay;
  c.history_.fill(Lanes::Zero());
  c.a_ = static_cast<Scalar>(g.a);
  c.b_ = static_cast<Scalar>(g.b);
  c.u_min_ = pad(Eigen::Matrix<double, N, 1>(g.u_min).template cast<Scalar>());
  c.u_max_ = pad(Eigen::Matrix<double, N, 1>(g.u_max).template cast<Scalar>());
  return c;
}

}  // namespace flexloop::controller::runtime
