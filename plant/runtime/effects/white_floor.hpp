// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Band-limited white floor acceleration: w_k = rms * n_k, n_k independent standard normal per
// channel (seeded). The flat-spectrum alternative to FloorGenerator, with the same step().
#include <cstdint>

#include "plant/runtime/effects/gaussian_noise.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class WhiteFloor {
 public:
  using Vector = ChannelVector<Scalar, N>;
  /// @throws std::invalid_argument for a negative or non-finite rms.
  /// n channels: N when N is compiled in, 1 .. kMaxChannels for N = Eigen::Dynamic.
  static WhiteFloor from_parameters(double rms, std::uint64_t seed, Eigen::Index n = N) {
    require(std::isfinite(rms) && rms >= 0, "white floor", "rms must be finite and >= 0");
    return WhiteFloor(static_cast<Scalar>(rms), GaussianNoise<Scalar, N>::from_seed(seed, n));
  }
  Vector step() noexcept { return rms_ * noise_.sample(); }

 private:
  WhiteFloor(Scalar rms, GaussianNoise<Scalar, N> noise) : rms_(rms), noise_(noise) {}
  Scalar rms_;
  GaussianNoise<Scalar, N> noise_;
};

}  // namespace flexloop::plant::runtime::effects
