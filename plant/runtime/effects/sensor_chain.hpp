// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A sensor as the hardware has it: gain error, then white noise, then the ADC, then a delay of
// D samples (doc/design.md §6):   y_k = Q((1 + eps) x_{k-D} ... ) — precisely
//   g = (1 + eps) x,   n = g + sigma * normal,   q = quantise(n),   y_k = q_{k-D}.
// All four stages are present in a sensor (neutral values are allowed: eps = 0, sigma = 0,
// D = 0); a scene without the sensor does not instantiate this type at all.
#include <cstdint>

#include "plant/runtime/effects/additive_noise.hpp"
#include "plant/runtime/effects/gain_error.hpp"
#include "plant/runtime/effects/quantiser.hpp"
#include "plant/runtime/effects/sample_delay.hpp"

namespace flexloop::plant::runtime::effects {

template <int N>
struct SensorParameters {
  /// Neutral parameters for n channels (n = N when N is compiled in).
  SensorParameters() : SensorParameters(N == Eigen::Dynamic ? 1 : N) {}
  explicit SensorParameters(Eigen::Index n)
      : gain_error(ChannelParameters<N>::Zero(n)),
        noise_rms(ChannelParameters<N>::Zero(n)),
        adc_range(ChannelParameters<N>::Ones(n)) {}
  ChannelParameters<N> gain_error;  ///< relative, eps
  ChannelParameters<N> noise_rms;   ///< sigma, SI units
  int adc_bits = 16;
  ChannelParameters<N> adc_range;  ///< full-scale range, SI
  int delay_samples = 0;
  std::uint64_t seed = 1;
};

template <class Scalar, int N>
class SensorChain {
 public:
  using Vector = ChannelVector<Scalar, N>;

  /// @throws std::invalid_argument from the stages (naming the stage and the value).
  static SensorChain from_parameters(const SensorParameters<N>& p) {
    return SensorChain(
        GainError<Scalar, N>::from_parameters(p.gain_error),
        AdditiveNoise<Scalar, N>::from_parameters(p.noise_rms, p.seed),
        Quantiser<Scalar, N>::from_parameters(p.adc_bits, p.adc_range),
        SampleDelay<Scalar, N>::from_parameters(p.delay_samples, p.noise_rms.size()));
  }

  /// The reading `back` samples ago, 1 <= back <= delay (a run's start; the ADC's rounding left
  /// out).
  void set_past(int back, const Vector& q) noexcept { delay_.set_past(back, q); }
  int delay() const noexcept { return delay_.delay(); }

  Vector step(const Vector& x) noexcept {
    return delay_.step(adc_.step(noise_.step(gain_.step(x))));
  }

 private:
  SensorChain(GainError<Scalar, N> g, AdditiveNoise<Scalar, N> n, Quantiser<Scalar, N> q,
              SampleDelay<Scalar, N> d)
      : gain_(g), noise_(n), adc_(q), delay_(d) {}
  GainError<Scalar, N> gain_;
  AdditiveNoise<Scalar, N> noise_;
  Quantiser<Scalar, N> adc_;
  SampleDelay<Scalar, N> delay_;
};

}  // namespace flexloop::plant::runtime::effects
