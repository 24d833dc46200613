// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// N independent standard normal sequences n_k (mean 0, variance 1), one per channel, for the
// sensor noise and the floor generator.
//
// Channel c draws from its own xoshiro256++ stream c of the seed (xoshiro256.hpp) through the
// ziggurat (ziggurat_normal.hpp); the channels draw side by side, kLanes to a group of SIMD lanes,
// so a sample of 18 channels costs a few group draws instead of 18 scalar ones. Cast to Scalar, so
// float and double runs see the same numbers. Channel c's sequence depends only on (seed, c), not
// on N, and is the same on every build and platform (the engine and the ziggurat's usual path are
// exact integer and IEEE arithmetic on a fixed table). Give every effect its own seed: two
// effects with one seed get the same numbers.
// The draws are made one sample ahead: sample() returns the draws made before and then draws the
// next ones, so the lanes' wide stores are long done when a sample is read (a narrower load from
// a store still in flight waits for it: 16 % of a `sim` step on Zen 5) and the draws overlap the
// caller's work instead of heading its dependency chain. Each channel's sequence is unchanged.
// Memory: 32 bytes of engine state and 8 of draw ahead per lane, in place (for N =
// Eigen::Dynamic the lanes of kMaxChannels channels, of which the first n draw). A draw costs no
// allocation and no system call.
#include <algorithm>
#include <array>
#include <cstdint>

#include "numeric/column_product.hpp"
#include "plant/runtime/effects/channels.hpp"
#include "plant/runtime/effects/ziggurat_normal.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class GaussianNoise {
  static_assert(kValidChannels<Scalar, N>);

 public:
  /// n channels: N when N is compiled in, 1 .. kMaxChannels for N = Eigen::Dynamic.
  static GaussianNoise from_seed(std::uint64_t seed, Eigen::Index n = N) {
    GaussianNoise g;
    g.n_ = channel_count<N>("gaussian noise", n);
    for (int group = 0; group < kGroups; ++group)
      g.groups_[group] = ziggurat::EngineLanes(seed, std::uint64_t{kLanes} * group);
    g.draw_ahead();
    return g;
  }

  /// One draw per channel.
  ChannelVector<Scalar, N> sample() noexcept {
    const ChannelVector<Scalar, N> draws =
        Eigen::Map<const ChannelVector<double, N>>(ahead_.data(), n_).template cast<Scalar>();
    draw_ahead();
    return draws;
  }

  /// sample() as NP lanes: the draws, then zeros (NP >= channels()), for a caller that runs the
  /// channels side by side in NP lanes (numeric/column_product.hpp): read in one piece.
  template <int NP>
  Eigen::Matrix<Scalar, NP, 1> sample_lanes() noexcept {
    static_assert(NP <= kAhead, "sample_lanes: more lanes than the draws ahead hold");
    const Eigen::Matrix<Scalar, NP, 1> draws =
        Eigen::Map<const Eigen::Matrix<double, NP, 1>>(ahead_.data()).template cast<Scalar>();
    draw_ahead();
    return draws;
  }

  /// The next draw of channel c alone (0 <= c < channels(), unchecked).
  Scalar sample(int c) noexcept {
    const double draw = ahead_[c];
    ahead_[c] = groups_[c / kLanes].normal(c % kLanes);
    return static_cast<Scalar>(draw);
  }

  int channels() const noexcept { return n_; }

 private:
  static constexpr int kLanes = ziggurat::kLanes;
  static constexpr int kGroups = (numeric::kChannelRows<N> + kLanes - 1) / kLanes;
  // The draws ahead, zero-padded to whole groups or to the channels' SIMD lanes if wider.
  static constexpr int kAhead =
      std::max(kGroups * kLanes, numeric::kPaddedRows<Scalar, numeric::kChannelRows<N>>);

  GaussianNoise() = default;

  // The lanes of a partial last group are scratch: zero them (sample_lanes pads with zeros).
  void draw_ahead() noexcept {
    int first = 0;
    for (int group = 0; first < n_; ++group, first += kLanes)
      groups_[group].normals(ahead_.data() + first, std::min(kLanes, n_ - first));
    for (int l = n_; l < first; ++l) ahead_[l] = 0;
  }

  std::array<ziggurat::EngineLanes, kGroups> groups_;
  alignas(64) std::array<double, kAhead> ahead_{};  // the next sample's draws, then zeros
  int n_ = 0;
};

}  // namespace flexloop::plant::runtime::effects
