// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The campaign's own random numbers: counter-based, so a number depends only on its key (seed,
// stream, counter) and is the same on every machine and in every order of evaluation (no std::
// engine or distribution, whose output the standard leaves to the implementation).
//
// The mixer is SplitMix64's finaliser (Steele, Lea, Flood 2014: "Fast splittable pseudorandom
// number generators"), applied once per key word: bits = mix(mix(mix(seed) ^ a) ^ b).
#include <cstdint>

namespace flexloop::campaign {

/// SplitMix64's output function of x + golden gamma: a bijection of 64-bit words that avalanches.
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// 64 random bits for the key (seed, a, b).
constexpr std::uint64_t counter_bits(std::uint64_t seed, std::uint64_t a, std::uint64_t b) {
  return splitmix64(splitmix64(splitmix64(seed) ^ a) ^ b);
}

/// The top 53 bits as a double in [0, 1): exact (k / 2^53), never 1.
constexpr double unit_from_bits(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1p-53;
}

/// A sequence of random words for one (seed, stream): word k is counter_bits(seed, stream, k).
class CounterStream {
 public:
  constexpr CounterStream(std::uint64_t seed, std::uint64_t stream)
      : seed_(seed), stream_(stream) {}
  constexpr std::uint64_t next() { return counter_bits(seed_, stream_, counter_++); }
  constexpr double unit() { return unit_from_bits(next()); }
  /// Uniform on {0, ..., bound - 1} without bias (Lemire 2019, multiply-shift with rejection).
  std::uint64_t below(std::uint64_t bound) {
    __extension__ typedef unsigned __int128 u128;  // GCC and Clang: the 128-bit product
    const std::uint64_t threshold = static_cast<std::uint64_t>(-bound) % bound;  // 2^64 mod bound
    while (true) {
      const u128 m = static_cast<u128>(next()) * bound;
      if (static_cast<std::uint64_t>(m) >= threshold) return static_cast<std::uint64_t>(m >> 64);
    }
  }

 private:
  std::uint64_t seed_, stream_, counter_ = 0;
};

}  // namespace flexloop::campaign
