// SPDX-License-Identifier: BSD-3-Clause
// ADC quantiser: every grid value maps to itself, everything within half an LSB of a level maps
// to that level, ties go to the even code, values beyond the range clip to the end codes — all
// exact (the LSBs here are powers of two, so no rounding is involved); for a range that is not a
// power of two the reading is a level within q/2 of the input.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "plant/runtime/effects/quantiser.hpp"

using namespace flexloop::plant::runtime::effects;

namespace {
using V2 = ChannelVector<double, 2>;
V2 both(double x) {
  return V2::Constant(x);
}
}  // namespace

TEST_CASE("quantiser: grid values, half-LSB neighbourhoods and ties are exact (mid-tread)") {
  // 8 bits over 2.0 peak to peak: q = 1/128, codes -128 .. 127.
  const auto adc = Quantiser<double, 2>::from_parameters(8, both(2.0));
  const double q = 1.0 / 128;
  CHECK(adc.lsb()(0) == q);
  for (int k = -128; k <= 127; ++k) {
    INFO("code " << k);
    CHECK(adc.step(both(k * q))(0) == k * q);
    CHECK(adc.step(both(k * q + 0.49 * q))(0) == k * q);
    CHECK(adc.step(both(k * q - 0.49 * q))(0) == k * q);
    // A tie k + 1/2 goes to whichever of k, k + 1 is even.
    if (k < 127) CHECK(adc.step(both((k + 0.5) * q))(0) == ((k % 2 == 0) ? k : k + 1) * q);
  }
  CHECK(adc.step(both(0.0))(0) == 0.0);  // zero is a level
  CHECK(adc.step(both(-0.0))(0) == 0.0);
}

TEST_CASE("quantiser: clips at the end codes, ±inf included, NaN stays NaN") {
  const auto adc = Quantiser<double, 2>::from_parameters(8, both(2.0));
  const double q = 1.0 / 128;
  CHECK(adc.step(both(1.0))(0) == 127 * q);  // +full scale is beyond the last code
  CHECK(adc.step(both(127.4 * q))(0) == 127 * q);
  CHECK(adc.step(both(1e9))(0) == 127 * q);
  CHECK(adc.step(both(-1.0))(0) == -1.0);  // -full scale is the first code
  CHECK(adc.step(both(-1e9))(0) == -1.0);
  CHECK(adc.step(both(std::numeric_limits<double>::infinity()))(0) == 127 * q);
  CHECK(adc.step(both(-std::numeric_limits<double>::infinity()))(0) == -1.0);
  CHECK(std::isnan(adc.step(both(std::numeric_limits<double>::quiet_NaN()))(0)));
}

namespace {
// Every channel of an n-channel quantiser (each in another SIMD position, a tail included) clips
// ±inf and large values to the end codes, keeps NaN and rounds to even at a tie.
template <class Scalar, int N>
void check_every_channel(Eigen::Index n) {
  const auto adc = Quantiser<Scalar, N>::from_parameters(8, ChannelParameters<N>::Constant(n, 2));
  const Scalar q = Scalar(1) / 128, inf = std::numeric_limits<Scalar>::infinity();
  const Scalar nan = std::numeric_limits<Scalar>::quiet_NaN();
  for (Eigen::Index c = 0; c < n; ++c) {
    INFO(n << " channels, channel " << c);
    for (const Scalar other : {Scalar(0), nan, inf}) {
      ChannelVector<Scalar, N> x = ChannelVector<Scalar, N>::Constant(n, other);
      x(c) = nan;
      CHECK(std::isnan(adc.step(x)(c)));
      x(c) = inf;
      CHECK(adc.step(x)(c) == 127 * q);
      x(c) = -inf;
      CHECK(adc.step(x)(c) == -1);
      x(c) = Scalar(1e9);
      CHECK(adc.step(x)(c) == 127 * q);
      x(c) = Scalar(2.5) * q;
      CHECK(adc.step(x)(c) == 2 * q);
    }
  }
}
}  // namespace

TEST_CASE("quantiser: every channel of any count clips, keeps NaN and rounds ties to even") {
  check_every_channel<double, 1>(1);
  check_every_channel<double, 3>(3);
  check_every_channel<double, 6>(6);
  check_every_channel<double, 7>(7);
  check_every_channel<double, 12>(12);
  check_every_channel<float, 6>(6);
  check_every_channel<float, 9>(9);
  for (const Eigen::Index n : {1, 5, 6, 13, 64}) {
    check_every_channel<double, Eigen::Dynamic>(n);
    check_every_channel<float, Eigen::Dynamic>(n);
  }
}

TEST_CASE("quantiser: per-channel ranges, a reading is a level within q/2 (16 bits, 20 N range)") {
  ChannelVector<double, 2> range;
  range << 20.0, 3.0;
  const auto adc = Quantiser<double, 2>::from_parameters(16, range);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int i = 0; i < 100000; ++i) {
    ChannelVector<double, 2> x;
    x << u(rng) * 10, u(rng) * 1.5;
    const auto y = adc.step(x);
    for (int c = 0; c < 2; ++c) {
      const double q = range(c) / 65536, code = y(c) / q;
      REQUIRE(std::abs(code - std::round(code)) <= 1e-9);
      REQUIRE(std::round(code) >= -32768);
      REQUIRE(std::round(code) <= 32767);
      const bool inside = x(c) >= -range(c) / 2 && x(c) <= range(c) / 2 - q;
      if (inside)
        REQUIRE(std::abs(y(c) - x(c)) <= 0.5 * q * (1 + 1e-12));
      else
        REQUIRE(std::abs(y(c)) >= range(c) / 2 - q);
    }
  }
}

TEST_CASE("quantiser: float holds a 24-bit converter exactly") {
  const auto adc = Quantiser<float, 1>::from_parameters(24, ChannelParameters<1>::Constant(2.0));
  const float q = std::ldexp(1.0f, -23);
  for (int k : {-8388608, -8388607, -1, 0, 1, 4194303, 8388607}) {
    INFO("code " << k);
    CHECK(adc.step(ChannelVector<float, 1>::Constant(k * q))(0) == k * q);
  }
  CHECK(adc.step(ChannelVector<float, 1>::Constant(1.0f))(0) == 8388607 * q);
}

TEST_CASE("quantiser: start-up rejects bad bits and ranges") {
  CHECK_THROWS_WITH((Quantiser<double, 2>::from_parameters(0, both(1.0))),
                    Catch::Contains("bits is 0, must be 1 .. 53"));
  CHECK_THROWS_WITH((Quantiser<float, 2>::from_parameters(25, both(1.0))),
                    Catch::Contains("must be 1 .. 24"));
  CHECK_THROWS_WITH((Quantiser<double, 2>::from_parameters(16, both(0.0))),
                    Catch::Contains("full-scale range of channel 0"));
  CHECK_THROWS_AS((Quantiser<double, 2>::from_parameters(16, both(std::nan("")))),
                  std::invalid_argument);
}
