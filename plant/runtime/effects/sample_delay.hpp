// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Pure delay of D samples:  y_k = x_{k-D}, and y_k = the initial value (zero unless reset) for
// k < D. D is chosen at start-up, 0 <= D <= kMaxDelay (a compile-time bound that sizes the ring
// buffer: kMaxDelay + 1 vectors); D = 0 passes the input through. For sensor latency and for the
// transport delay between plant and controller.
#include <array>

#include "plant/runtime/effects/channels.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N, int kMaxDelay = 32>
class SampleDelay {
  static_assert(kValidChannels<Scalar, N> && kMaxDelay >= 0);

 public:
  /// @throws std::invalid_argument unless 0 <= delay <= kMaxDelay.
  /// n channels: N when N is compiled in, 1 .. kMaxChannels for N = Eigen::Dynamic.
  static SampleDelay from_parameters(int delay, Eigen::Index n = N) {
    require(delay >= 0 && delay <= kMaxDelay, "sample delay",
            "delay is " + std::to_string(delay) + " samples, must be 0 .. " +
                std::to_string(kMaxDelay) + " (the compile-time maximum)");
    return SampleDelay(delay, channel_count<N>("sample delay", n));
  }

  /// Fills the line with `value`: the next D outputs.
  void reset(const ChannelVector<Scalar, N>& value) noexcept { ring_.fill(value); }

  /// x_{k-back} for the next step at k, 1 <= back <= D (a run's start); unchecked.
  void set_past(int back, const ChannelVector<Scalar, N>& x) noexcept {
    const int i = head_ - back;
    ring_[i < 0 ? i + delay_ + 1 : i] = x;
  }

  // Ring of D + 1 slots: write x_k at head, then the slot after head holds x_{k-D}. D = 0 (a
  // sensor without latency, the usual case) passes x through without the ring's two copies.
  ChannelVector<Scalar, N> step(const ChannelVector<Scalar, N>& x) noexcept {
    if (delay_ == 0) return x;
    ring_[head_] = x;
    head_ = head_ == delay_ ? 0 : head_ + 1;
    return ring_[head_];
  }

  int delay() const noexcept { return delay_; }

 private:
  SampleDelay(int delay, int n) : delay_(delay) { reset(ChannelVector<Scalar, N>::Zero(n)); }
  std::array<ChannelVector<Scalar, N>, kMaxDelay + 1> ring_;
  int delay_;
  int head_ = 0;
};

/// The transport from the plant to the controller: the same delay on the NS sensor and the NZ
/// performance channels.
template <class Scalar, int NS, int NZ>
struct TransportDelay {
  SampleDelay<Scalar, NS> sensors;
  SampleDelay<Scalar, NZ> performance;

  /// @throws std::invalid_argument as SampleDelay::from_parameters.
  static TransportDelay from_parameters(int delay, Eigen::Index ns = NS, Eigen::Index nz = NZ) {
    return {SampleDelay<Scalar, NS>::from_parameters(delay, ns),
            SampleDelay<Scalar, NZ>::from_parameters(delay, nz)};
  }
};

}  // namespace flexloop::plant::runtime::effects
