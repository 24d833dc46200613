// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// First-order lag τ df/dt = -f + v per channel, discretised exactly for an input v held constant
// over each sample [kT, (k+1)T) (zero-order hold):
//   a = e^(-T/τ),   f_{k+1} = v_k + (f_k - v_k) a                  (value at the next instant)
//   b = (τ/T)(1 - a),  f̄_k = (1/T) ∫ f dt over the sample = v_k + (f_k - v_k) b
// step() returns f̄_k, the sample's mean: a zero-order-hold plant driven by it receives exactly the
// impulse ∫ f dt the continuous lag delivers, which f_k or f_{k+1} would not (their error is
// O(T/τ), the mean's O((T/τ)²) in the response). state() is f at the sample instants.
// For a unit step from rest, f(kT) = 1 - e^(-kT/τ) and f̄_k = 1 - (τ/T) e^(-kT/τ)(1 - a).
#include <cmath>

#include "plant/runtime/effects/channels.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class FirstOrderLag {
  static_assert(kValidChannels<Scalar, N>);

 public:
  /// @throws std::invalid_argument unless every τ [s] and dt [s] are finite and > 0.
  static FirstOrderLag from_parameters(const ChannelParameters<N>& time_constant, double dt) {
    require(std::isfinite(dt) && dt > 0, "first-order lag",
            "sample time is " + std::to_string(dt) + " s, must be finite and > 0");
    require_each<N>(time_constant, "first-order lag", "time constant [s]", "> 0",
                    [](double v) { return v > 0; });
    const int n = channel_count<N>("first-order lag", time_constant.size());
    ChannelParameters<N> a(n), b(n);
    for (int c = 0; c < n; ++c) {
      const double one_minus_a = -std::expm1(-dt / time_constant(c));  // accurate for T << τ
      a(c) = 1 - one_minus_a;
      b(c) = time_constant(c) / dt * one_minus_a;
    }
    return FirstOrderLag(a.template cast<Scalar>(), b.template cast<Scalar>());
  }

  /// Sets the state f to `value` (e.g. the first command, for a bumpless start).
  void reset(const ChannelVector<Scalar, N>& value) noexcept { state_ = value; }

  /// Input v_k held over the sample; returns the sample's mean f̄_k and advances to f_{k+1}.
  ChannelVector<Scalar, N> step(const ChannelVector<Scalar, N>& v) noexcept {
    const ChannelVector<Scalar, N> offset = state_ - v;
    state_ = v + offset.cwiseProduct(a_);
    return v + offset.cwiseProduct(b_);
  }

  /// f at the current sample instant.
  const ChannelVector<Scalar, N>& state() const noexcept { return state_; }

 private:
  FirstOrderLag(const ChannelVector<Scalar, N>& a, const ChannelVector<Scalar, N>& b)
      : a_(a), b_(b), state_(ChannelVector<Scalar, N>::Zero(a.size())) {}
  ChannelVector<Scalar, N> a_, b_, state_;
};

}  // namespace flexloop::plant::runtime::effects
