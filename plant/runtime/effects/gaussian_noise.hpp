#pragma once
// N independent standard normal sequences n_k (mean 0, variance 1), one per channel, for the
// sensor noise and the floor generator.
//
// Channel c draws from its own xoshiro256++ stream c of the seed (xoshiro256.hpp), and
// Boost.Random's normal_distribution<double> (Marsaglia and Tsang's ziggurat: about 1.1 engine
// draws per normal, no logarithm or square root on the usual path; about twice as fast as
// std::normal_distribution's polar method here). Cast to Scalar, so float and double runs see the
// same numbers. Channel c's sequence depends only on (seed, c), not on N. Reproducibility: the
// same seed gives the same sequence on every build and platform (the engine is fully specified,
// the ziggurat is Boost's code, not the standard library's implementation-defined transform).
// Give every effect its own seed: two effects with one seed get the same numbers.
// Memory: 32 bytes of engine state per channel (for N = Eigen::Dynamic in a vector sized at
// start-up). A draw costs no allocation and no system call.
#include <array>
#include <boost/random/normal_distribution.hpp>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "plant/runtime/effects/channels.hpp"
#include "plant/runtime/effects/xoshiro256.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class GaussianNoise {
  static_assert(kValidChannels<Scalar, N>);

 public:
  /// n channels: N when N is compiled in, 1 .. kMaxChannels for N = Eigen::Dynamic.
  static GaussianNoise from_seed(std::uint64_t seed, Eigen::Index n = N) {
    GaussianNoise g;
    g.n_ = channel_count<N>("gaussian noise", n);
    if constexpr (N == Eigen::Dynamic) {
      g.engines_.resize(static_cast<std::size_t>(g.n_));
      g.normals_.resize(static_cast<std::size_t>(g.n_));
    }
    for (int c = 0; c < g.n_; ++c) g.engines_[c] = Xoshiro256PlusPlus(seed, c);
    return g;
  }

  /// One draw per channel.
  ChannelVector<Scalar, N> sample() noexcept {
    ChannelVector<Scalar, N> n(n_);
    for (int c = 0; c < n_; ++c) n(c) = sample(c);
    return n;
  }

  /// The next draw of channel c (0 <= c < channels(), unchecked).
  Scalar sample(int c) noexcept { return static_cast<Scalar>(normals_[c](engines_[c])); }

  int channels() const noexcept { return n_; }

 private:
  // Fixed N: in place; N = Eigen::Dynamic: sized once at start-up.
  template <class T>
  using PerChannel = std::conditional_t<N == Eigen::Dynamic, std::vector<T>, std::array<T, N>>;

  GaussianNoise() = default;
  PerChannel<Xoshiro256PlusPlus> engines_;
  PerChannel<boost::random::normal_distribution<double>> normals_;
  int n_ = 0;
};

}  // namespace flexloop::plant::runtime::effects
