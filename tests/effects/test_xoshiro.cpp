// SPDX-License-Identifier: BSD-3-Clause
// The noise effects' engine (plant/runtime/effects/xoshiro256.hpp) against the published
// algorithms: xoshiro256++'s first output from the state {1, 2, 3, 4} is rotl(1 + 4, 23) + 1 by
// its definition, the following ones and the seeded streams come from an independent
// implementation (Python, integers of unlimited size, masked to 64 bits), and SplitMix64's first
// output from 0 is the value its authors' reference code prints.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include "plant/runtime/effects/gaussian_noise.hpp"
#include "plant/runtime/effects/xoshiro256.hpp"

using namespace flexloop::plant::runtime::effects;

static_assert(std::uniform_random_bit_generator<Xoshiro256PlusPlus>);

TEST_CASE("xoshiro256++: the published algorithm, output by output", "[effects][noise]") {
  Xoshiro256PlusPlus g(std::array<std::uint64_t, 4>{1, 2, 3, 4});
  CHECK(g() == (5ull << 23) + 1);  // 41943041
  CHECK(g() == 58720359ull);
  CHECK(g() == 3588806011781223ull);
  CHECK(g() == 3591011842654386ull);
  CHECK(g() == 9228616714210784205ull);
  CHECK(SplitMix64(0)() == 0xE220A8397B1DCDAFull);
}

TEST_CASE("xoshiro256++: stream c of a seed starts from SplitMix64's outputs 4c+1 .. 4c+4",
          "[effects][noise]") {
  // Seed 42, stream 1: SplitMix64(42)'s outputs 5 .. 8 as the state.
  Xoshiro256PlusPlus g(42, 1);
  CHECK(g() == 3323035867591966009ull);
  CHECK(g() == 7886305442867161247ull);
  CHECK(g() == 6930324258397534950ull);
  // Streams of one seed, and one stream of two seeds, differ.
  CHECK(Xoshiro256PlusPlus(42, 0)() != Xoshiro256PlusPlus(42, 1)());
  CHECK(Xoshiro256PlusPlus(42, 0)() != Xoshiro256PlusPlus(43, 0)());
}

TEST_CASE("gaussian noise: unit normal per channel, channels uncorrelated, independent of N",
          "[effects][noise]") {
  constexpr int kDraws = 200000;
  auto noise = GaussianNoise<double, 3>::from_seed(7);
  double sum[3] = {}, sum2[3] = {}, cross01 = 0, cross12 = 0, kurt0 = 0;
  for (int k = 0; k < kDraws; ++k) {
    const auto n = noise.sample();
    for (int c = 0; c < 3; ++c) {
      sum[c] += n(c);
      sum2[c] += n(c) * n(c);
    }
    cross01 += n(0) * n(1);
    cross12 += n(1) * n(2);
    kurt0 += std::pow(n(0), 4);
  }
  // Standard errors over kDraws: mean 1/sqrt(K), variance sqrt(2/K), correlation 1/sqrt(K),
  // fourth moment sqrt(96/K); bounds of five standard errors.
  const double se = 1 / std::sqrt(double{kDraws});
  for (int c = 0; c < 3; ++c) {
    CHECK(std::abs(sum[c] / kDraws) < 5 * se);
    CHECK(std::abs(sum2[c] / kDraws - 1) < 5 * std::sqrt(2.0) * se);
  }
  CHECK(std::abs(cross01 / kDraws) < 5 * se);
  CHECK(std::abs(cross12 / kDraws) < 5 * se);
  CHECK(std::abs(kurt0 / kDraws - 3) < 5 * std::sqrt(96.0) * se);
  // Channel 1's sequence does not depend on how many channels there are.
  auto one = GaussianNoise<double, Eigen::Dynamic>::from_seed(7, 2);
  auto three = GaussianNoise<double, 3>::from_seed(7);
  for (int k = 0; k < 100; ++k) CHECK(one.sample()(1) == three.sample()(1));
}
