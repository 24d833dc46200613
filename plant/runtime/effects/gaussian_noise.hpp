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
// Memory: 32 bytes of engine state per lane, in place (for N = Eigen::Dynamic the lanes of
// kMaxChannels channels, of which the first n draw). A draw costs no allocation and no system
// call.
#include <algorithm>
#include <array>
#include <cstdint>

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
    return g;
  }

  /// One draw per channel.
  ChannelVector<Scalar, N> sample() noexcept {
    alignas(64) double draws[kGroups * kLanes];
    for (int group = 0, first = 0; first < n_; ++group, first += kLanes)
      groups_[group].normals(draws + first, std::min(kLanes, n_ - first));
    return Eigen::Map<const ChannelVector<double, N>>(draws, n_).template cast<Scalar>();
  }

  /// The next draw of channel c alone (0 <= c < channels(), unchecked).
  Scalar sample(int c) noexcept {
    return static_cast<Scalar>(groups_[c / kLanes].normal(c % kLanes));
  }

  int channels() const noexcept { return n_; }

 private:
  static constexpr int kLanes = ziggurat::kLanes;
  static constexpr int kGroups = (kChannelRows<N> + kLanes - 1) / kLanes;

  GaussianNoise() = default;
  std::array<ziggurat::EngineLanes, kGroups> groups_;
  int n_ = 0;
};

}  // namespace flexloop::plant::runtime::effects
