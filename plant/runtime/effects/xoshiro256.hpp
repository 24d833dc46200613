// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// xoshiro256++ (Blackman and Vigna, "Scrambled linear pseudorandom number generators", 2021): a
// 64-bit generator with 256 bits of state and period 2^256 - 1 that passes BigCrush and PractRand,
// at about a nanosecond per draw. The noise effects draw one sequence per channel; with
// std::mt19937_64 (2.5 kB of state each) the 18 channels of a scene with floor and sensors took
// 45 kB, most of the first-level cache (18 normal draws: 77 ns with this engine, 83 ns with
// mt19937_64, tests/bench/bench_effects.cpp; the normal transform is the larger part).
// A stream is seeded as the authors advise, from SplitMix64: stream c of seed s takes SplitMix64's
// outputs 4c + 1 .. 4c + 4 from state s, so the streams of one seed start from distinct outputs
// of a bijection, and stream c depends only on (s, c). Satisfies
// std::uniform_random_bit_generator; no allocation, no system call.
#include <array>
#include <cstdint>

namespace flexloop::plant::runtime::effects {

/// SplitMix64 (Steele, Lea and Flood, 2014): the seeding generator.
class SplitMix64 {
 public:
  explicit constexpr SplitMix64(std::uint64_t state) noexcept : state_(state) {}
  constexpr std::uint64_t operator()() noexcept {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

class Xoshiro256PlusPlus {
 public:
  using result_type = std::uint64_t;
  static constexpr result_type min() noexcept { return 0; }
  static constexpr result_type max() noexcept { return ~result_type{0}; }

  /// Stream `stream` of `seed` (see the header comment).
  explicit constexpr Xoshiro256PlusPlus(std::uint64_t seed = 0, std::uint64_t stream = 0) noexcept
      : s_{} {
    SplitMix64 seeder(seed + 4 * stream * 0x9E3779B97F4A7C15ull);
    for (auto& word : s_) word = seeder();
  }
  /// A given state (not all zero).
  explicit constexpr Xoshiro256PlusPlus(const std::array<std::uint64_t, 4>& state) noexcept
      : s_(state) {}

  constexpr result_type operator()() noexcept {
    const std::uint64_t result = rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// The 256 bits of state.
  constexpr const std::array<std::uint64_t, 4>& state() const noexcept { return s_; }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) noexcept {
    return (x << k) | (x >> (64 - k));
  }
  std::array<std::uint64_t, 4> s_;
};

}  // namespace flexloop::plant::runtime::effects
