// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Additive white Gaussian sensor noise:  y_k = x_k + σ ⊙ n_k,  n_k ~ N(0, I) from GaussianNoise
// (per-channel engines, reproducible for a seed; see gaussian_noise.hpp). σ [sensor unit, RMS]
// per channel, >= 0. The noise is white at the sample rate: its one-sided PSD is 2σ²/fs.
#include <cstdint>

#include "plant/runtime/effects/channels.hpp"
#include "plant/runtime/effects/gaussian_noise.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class AdditiveNoise {
 public:
  /// @throws std::invalid_argument unless every rms is finite and >= 0.
  static AdditiveNoise from_parameters(const ChannelParameters<N>& rms, std::uint64_t seed) {
    require_each<N>(rms, "sensor noise", "rms", ">= 0", [](double v) { return v >= 0; });
    return AdditiveNoise(rms.template cast<Scalar>(),
                         GaussianNoise<Scalar, N>::from_seed(seed, rms.size()));
  }

  ChannelVector<Scalar, N> step(const ChannelVector<Scalar, N>& x) noexcept {
    return x + rms_.cwiseProduct(noise_.sample());
  }

 private:
  AdditiveNoise(const ChannelVector<Scalar, N>& rms, const GaussianNoise<Scalar, N>& noise)
      : rms_(rms), noise_(noise) {}
  ChannelVector<Scalar, N> rms_;
  GaussianNoise<Scalar, N> noise_;
};

}  // namespace flexloop::plant::runtime::effects
