// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// ADC quantisation: a b-bit bipolar converter over the full-scale range R (peak to peak, centred
// on zero, per channel), mid-tread (zero is a level), two's-complement codes, clipping at range:
//   q = R / 2^b                                       (one LSB)
//   k = clamp(rint(x (1/q)), -2^(b-1), 2^(b-1) - 1)    (the code)
//   y = k q                                            (the reading, in the input's unit)
// rint rounds to nearest with ties to even in the default floating-point rounding mode (never
// changed in this program), so |y - x| <= q/2 inside the range. When q is a power of two, 1/q
// and x (1/q) are exact and so is the result; otherwise x (1/q) is within two roundings of x / q
// and a value that close to a tie may go either way (the product, not the quotient: a division's
// latency was the larger part of a sensor chain's step). ±inf clip to the end codes; NaN passes
// through as NaN (a fault stays visible). bits <= digits of Scalar (24 for float, 53 for double)
// so every code is exact.
#include <algorithm>
#include <cmath>
#include <limits>

#include "plant/runtime/effects/channels.hpp"

namespace flexloop::plant::runtime::effects {

template <class Scalar, int N>
class Quantiser {
  static_assert(kValidChannels<Scalar, N>);

 public:
  /// @throws std::invalid_argument unless 1 <= bits <= digits of Scalar and every range is
  ///         finite and > 0.
  static Quantiser from_parameters(int bits, const ChannelParameters<N>& full_scale_range) {
    constexpr int kMaxBits = std::numeric_limits<Scalar>::digits;
    require(bits >= 1 && bits <= kMaxBits, "quantiser",
            "bits is " + std::to_string(bits) + ", must be 1 .. " + std::to_string(kMaxBits));
    channel_count<N>("quantiser", full_scale_range.size());
    require_each<N>(full_scale_range, "quantiser", "full-scale range", "> 0",
                    [](double v) { return v > 0; });
    const double levels = std::ldexp(1.0, bits);
    return Quantiser((full_scale_range / levels).template cast<Scalar>(),
                     (levels * full_scale_range.cwiseInverse()).template cast<Scalar>(),
                     static_cast<Scalar>(-levels / 2), static_cast<Scalar>(levels / 2 - 1));
  }

  // One Eigen expression, like the stages around it: the same packets from end to end keep the
  // chain in registers (a loop here was vectorised with other widths than Eigen's, and each change
  // of width went through memory with a stalled store-to-load forward). max then min as std::max
  // and std::min: a NaN code stays NaN.
  ChannelVector<Scalar, N> step(const ChannelVector<Scalar, N>& x) const noexcept {
    return ((x.array() * per_lsb_.array()).rint().max(code_min_).min(code_max_) * lsb_.array())
        .matrix();
  }

  /// One LSB per channel, q = R / 2^b.
  const ChannelVector<Scalar, N>& lsb() const noexcept { return lsb_; }

 private:
  Quantiser(const ChannelVector<Scalar, N>& lsb, const ChannelVector<Scalar, N>& per_lsb,
            Scalar code_min, Scalar code_max)
      : lsb_(lsb), per_lsb_(per_lsb), code_min_(code_min), code_max_(code_max) {}
  ChannelVector<Scalar, N> lsb_;
  ChannelVector<Scalar, N> per_lsb_;  // 1/q
  Scalar code_min_, code_max_;
};

}  // namespace flexloop::plant::runtime::effects
