// SPDX-License-Identifier: BSD-3-Clause
// Sensor pieces: gain error and delay exact; white noise with the asked RMS and zero mean within
// 5 standard errors of the estimators (mean: σ/sqrt(n); variance: σ² sqrt(2/n) for Gaussian
// samples), uncorrelated in time and across channels (|r| < 5/sqrt(n)); same seed, same numbers.
#include <catch2/catch.hpp>
#include <cmath>

#include "plant/runtime/effects/additive_noise.hpp"
#include "plant/runtime/effects/gain_error.hpp"
#include "plant/runtime/effects/sample_delay.hpp"

using namespace flexloop::plant::runtime::effects;

TEST_CASE("gain error: y = (1 + ε) x exactly") {
  const ChannelParameters<3> eps(0.02, -0.5, 0.0);
  const auto g = GainError<double, 3>::from_parameters(eps);
  const ChannelVector<double, 3> x(3.0, -8.0, 1e-3);
  CHECK(g.step(x) == ChannelVector<double, 3>(1.02 * 3.0, 0.5 * -8.0, 1e-3));
  CHECK_THROWS_WITH((GainError<double, 3>::from_parameters({0.0, -1.0, 0.0})),
                    Catch::Contains("relative error of channel 1 is -1"));
}

TEST_CASE("sample delay: y_k = x_(k-D) exactly, the initial value before that") {
  for (const int d : {0, 1, 5, 16}) {
    auto line = SampleDelay<double, 2, 16>::from_parameters(d);
    line.reset(ChannelVector<double, 2>(-1.0, -2.0));
    for (int k = 0; k < 100; ++k) {
      const auto y = line.step(ChannelVector<double, 2>(k, 1000.0 + k));
      INFO("D = " << d << ", k = " << k);
      if (k < d)
        REQUIRE(y == ChannelVector<double, 2>(-1.0, -2.0));
      else
        REQUIRE(y == ChannelVector<double, 2>(k - d, 1000.0 + k - d));
    }
  }
  CHECK_THROWS_WITH((SampleDelay<double, 2, 16>::from_parameters(17)),
                    Catch::Contains("delay is 17 samples, must be 0 .. 16"));
  CHECK_THROWS_AS((SampleDelay<double, 2, 16>::from_parameters(-1)), std::invalid_argument);
}

TEST_CASE("additive noise: RMS and mean within 5 standard errors, white, channels independent") {
  constexpr int kN = 1 << 20;
  const ChannelParameters<3> rms(0.5, 2.0, 0.0);
  auto noise = AdditiveNoise<double, 3>::from_parameters(rms, 42);
  const ChannelVector<double, 3> offset(1.0, -3.0, 7.25);
  Eigen::Array3d sum = Eigen::Array3d::Zero(), sum2 = sum, lag1 = sum, previous = sum;
  double cross01 = 0;
  for (int k = 0; k < kN; ++k) {
    const Eigen::Array3d e = noise.step(offset).array() - offset.array();
    sum += e;
    sum2 += e * e;
    lag1 += e * previous;
    cross01 += e(0) * e(1);
    previous = e;
  }
  const double n = kN;
  for (int c = 0; c < 2; ++c) {
    const double s = rms(c), mean = sum(c) / n, var = sum2(c) / n;
    INFO("channel " << c << ": mean " << mean << ", rms " << std::sqrt(var));
    CHECK(std::abs(mean) <= 5 * s / std::sqrt(n));
    CHECK(std::abs(var / (s * s) - 1) <= 5 * std::sqrt(2 / n));
    CHECK(std::abs(lag1(c) / (n * s * s)) <= 5 / std::sqrt(n));
  }
  CHECK(std::abs(cross01 / (n * rms(0) * rms(1))) <= 5 / std::sqrt(n));
  CHECK(sum2(2) == 0);  // zero RMS leaves the signal exactly as it was
}

TEST_CASE("noise: same seed same sequence, other seed other sequence, channel c independent of N") {
  auto a = GaussianNoise<double, 6>::from_seed(1234), b = GaussianNoise<double, 6>::from_seed(1234);
  auto other = GaussianNoise<double, 6>::from_seed(1235);
  auto single = GaussianNoise<double, 1>::from_seed(1234);
  auto as_float = GaussianNoise<float, 6>::from_seed(1234);
  int differing = 0;
  for (int k = 0; k < 10000; ++k) {
    const auto x = a.sample(), y = b.sample(), z = other.sample();
    const auto s = single.sample();
    const auto f = as_float.sample();
    REQUIRE(x == y);
    REQUIRE(s(0) == x(0));
    REQUIRE(f == x.cast<float>());
    differing += (x.array() != z.array()).count();
    REQUIRE((x.array() != x(0)).count() == 5);  // the channels are not copies of each other
  }
  CHECK(differing == 60000);
}
