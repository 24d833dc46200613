#pragma once
// N independent standard normal sequences n_k (mean 0, variance 1), one per channel, for the
// sensor noise and the floor generator.
//
// Channel c draws from its own std::mt19937_64, seeded at start-up through
// std::seed_seq{seed mod 2^32, seed / 2^32, c}, and Boost.Random's normal_distribution<double>
// (Marsaglia and Tsang's ziggurat: about 1.1 engine draws per normal, no logarithm or square root
// on the usual path; about twice as fast as std::normal_distribution's polar method here). Cast
// to Scalar, so float and double runs see the same numbers. Channel c's sequence depends only on
// (seed, c), not on N. Reproducibility: the same seed gives the same sequence on every build and
// platform (std::mt19937_64 is exactly specified by the standard, the ziggurat is Boost's code,
// not the standard library's implementation-defined transform). Give every effect its own seed:
// two effects with one seed get the same numbers.
// Memory: one 2.5 kB engine per channel. A draw costs no allocation and no system call.
#include <array>
#include <boost/random/normal_distribution.hpp>
#include <cstdint>
#include <random>

#include "plant/runtime/effects/channels.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class GaussianNoise {
  static_assert(kValidChannels<Scalar, N>);

 public:
  static GaussianNoise from_seed(std::uint64_t seed) {
    GaussianNoise g;
    for (int c = 0; c < N; ++c) {
      std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                        static_cast<std::uint32_t>(c)};
      g.engines_[c].seed(seq);
    }
    return g;
  }

  /// One draw per channel.
  ChannelVector<Scalar, N> sample() noexcept {
    ChannelVector<Scalar, N> n;
    for (int c = 0; c < N; ++c) n(c) = sample(c);
    return n;
  }

  /// The next draw of channel c (0 <= c < N, unchecked).
  Scalar sample(int c) noexcept { return static_cast<Scalar>(normals_[c](engines_[c])); }

 private:
  GaussianNoise() = default;
  std::array<std::mt19937_64, N> engines_;
  std::array<boost::random::normal_distribution<double>, N> normals_;
};

}  // namespace flexloop::plant::runtime::effects
