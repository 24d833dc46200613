// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Sensor (or actuator) gain error:  y_k = (1 + ε) ⊙ x_k,  ε the relative error per channel
// (0.02 reads 2 % high), ε > -1 so the sign of the signal survives.
#include "plant/runtime/effects/channels.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class GainError {
  static_assert(kValidChannels<Scalar, N>);

 public:
  /// @throws std::invalid_argument unless every relative error is finite and > -1.
  static GainError from_parameters(const ChannelParameters<N>& relative_error) {
    require_each<N>(relative_error, "gain error", "relative error", "> -1",
                    [](double v) { return v > -1; });
    channel_count<N>("gain error", relative_error.size());
    return GainError((relative_error.array() + 1.0).matrix().template cast<Scalar>());
  }

  ChannelVector<Scalar, N> step(const ChannelVector<Scalar, N>& x) const noexcept {
    return gain_.cwiseProduct(x);
  }

 private:
  explicit GainError(const ChannelVector<Scalar, N>& gain) : gain_(gain) {}
  ChannelVector<Scalar, N> gain_;
};

}  // namespace flexloop::plant::runtime::effects
