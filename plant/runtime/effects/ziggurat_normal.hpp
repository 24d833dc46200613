// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Standard normal draws by the ziggurat (Marsaglia and Tsang, J. Stat. Softw. 5(8), 2000; 1024
// layers of equal area, ziggurat_table.hpp), from one 64-bit engine output on the usual path:
//   bits 0-9 the layer i, bit 10 the sign, bits 12-63 a uniform U in [0, 1) (52 bits; the layer
//   and the sign come from other bits than U, as Doornik (2005) advises),
//   x = U x_i, accepted when x < x_{i+1} (inside the curve for every height of the layer),
// otherwise, in layer 0 Marsaglia's exact tail beyond r, in layer i >= 1 the wedge test
// (one more draw: a height in [f(x_i), f(x_{i+1})] against f(x)); a rejected attempt starts over.
//
// The usual path (99.6 % of draws, tests/effects/test_ziggurat_normal.cpp; 1024 layers rather
// than 256 so that a group of lanes rarely has one to finish alone) is a few integer and
// floating-point operations without a branch on the data, so EngineLanes draws on kLanes engines
// side by side in SIMD lanes (GCC/Clang vector extensions: AVX-512, AVX2 or SSE2 as the build
// targets); a lane whose usual path rejects finishes alone on the same engine, so lane l's
// sequence is exactly what normal() gives on that engine alone. The usual path is exact integer
// and IEEE arithmetic on a table rounded once from 50 digits, the same on every platform; the
// rare wedge and tail use std::exp and std::log.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "plant/runtime/effects/xoshiro256.hpp"
#include "plant/runtime/effects/ziggurat_table.hpp"

namespace flexloop::plant::runtime::effects::ziggurat {

/// U in [0, 1) from bits 12-63 (exact: 1 + U is the double with those 52 mantissa bits).
inline double uniform(std::uint64_t bits) noexcept {
  return std::bit_cast<double>((bits >> 12) | 0x3FF0000000000000ull) - 1.0;
}
inline int layer(std::uint64_t bits) noexcept {
  return static_cast<int>(bits & (kLayers - 1));
}
/// value with bit 10 as its sign (without a branch: the sign is a coin toss).
inline double with_sign(std::uint64_t bits, double value) noexcept {
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(value) ^ (bits >> 10) << 63);
}

/// |x| beyond r with density proportional to f (Marsaglia 1964): x = -ln(U1) / r, y = -ln(U2),
/// accepted when 2y >= x^2; r + x.
template <class Engine>
double tail(Engine& engine) noexcept {
  for (;;) {
    const double x = -std::log(1.0 - uniform(engine())) / kTailStart;  // 1 - U in (0, 1]
    const double y = -std::log(1.0 - uniform(engine()));
    if (y + y >= x * x) return kTailStart + x;
  }
}

/// One attempt from the engine output `bits`: true with the draw in `x`, or false (rejected in a
/// wedge: start over with a new output).
template <class Engine>
bool attempt(std::uint64_t bits, Engine& engine, double& x) noexcept {
  const int i = layer(bits);
  double value = uniform(bits) * kEdge[i];
  if (value >= kEdge[i + 1]) {
    if (i == 0) {
      value = tail(engine);
    } else {
      const double height = kDensity[i] + uniform(engine()) * (kDensity[i + 1] - kDensity[i]);
      if (height >= std::exp(-0.5 * value * value)) return false;
    }
  }
  x = with_sign(bits, value);
  return true;
}

/// A standard normal draw from `engine`.
template <class Engine>
double normal(Engine& engine) noexcept {
  double x;
  while (!attempt(engine(), engine, x)) {
  }
  return x;
}

/// The draw that began with the engine output `bits` (already taken from `engine`).
template <class Engine>
double finish(std::uint64_t bits, Engine& engine) noexcept {
  double x;
  return attempt(bits, engine, x) ? x : normal(engine);
}

static_assert((kLayers & (kLayers - 1)) == 0 && kLayers <= 2048, "layer and sign in bits 0-11");

/// Lanes of one SIMD register of 64-bit words: 8 with AVX-512, 4 with AVX2, 2 otherwise (wider
/// vectors than the build's registers compile to slow code). A lane's draws do not depend on it.
#if defined(__AVX512F__)
inline constexpr int kLanes = 8;
#elif defined(__AVX2__)
inline constexpr int kLanes = 4;
#else
inline constexpr int kLanes = 2;
#endif

/// kLanes xoshiro256++ engines side by side: lane l is Xoshiro256PlusPlus(seed, first + l), and
/// normals() gives each lane the draw normal() would give on that engine alone.
class EngineLanes {
 public:
  EngineLanes() = default;
  EngineLanes(std::uint64_t seed, std::uint64_t first_stream) noexcept {
    for (int l = 0; l < kLanes; ++l) set_lane(l, Xoshiro256PlusPlus(seed, first_stream + l));
  }

  /// One standard normal draw per lane into x[0 .. kLanes - 1] (every lane's engine advances);
  /// lanes from `active` on are scratch (their rejected draws are not finished).
  void normals(double* x, int active) noexcept {
    Words bits;
    next(bits);
    const Words i = bits & (kLayers - 1);
    Reals edge, inner;
    gather(kEdge, i, edge);
    gather(kEdge + 1, i, inner);
    const Reals one_plus_u = std::bit_cast<Reals>((bits >> 12) | 0x3FF0000000000000ull);
    const Reals value = (one_plus_u - 1.0) * edge;
    const Masks rejected = value >= inner;
    const Words sign = (bits >> 10) << 63;
    const Reals draw = std::bit_cast<Reals>(std::bit_cast<Words>(value) ^ sign);
    std::memcpy(x, &draw, sizeof draw);
    unsigned finish_lanes = lane_bits(rejected) & ((1u << active) - 1);
    while (finish_lanes != 0) [[unlikely]] {
        const int l = std::countr_zero(finish_lanes);
        finish_lanes &= finish_lanes - 1;
        Xoshiro256PlusPlus engine = lane(l);
        x[l] = finish(bits[l], engine);
        set_lane(l, engine);
      }
  }

  /// The next draw of lane l alone.
  double normal(int l) noexcept {
    Xoshiro256PlusPlus engine = lane(l);
    const double x = ziggurat::normal(engine);
    set_lane(l, engine);
    return x;
  }

 private:
  typedef std::uint64_t Words __attribute__((vector_size(8 * kLanes)));
  typedef double Reals __attribute__((vector_size(8 * kLanes)));
  typedef std::int64_t Masks __attribute__((vector_size(8 * kLanes)));

  // out[l] = table[index[l]] on every lane. A gather instruction where the build has one:
  // assembling the vector through memory lane by lane stalls on store forwarding, which cost more
  // than the rest of the draw.
  static void gather(const double* table, const Words& index, Reals& out) noexcept {
#if defined(__AVX512F__)
    out = std::bit_cast<Reals>(_mm512_i64gather_pd(std::bit_cast<__m512i>(index), table, 8));
#elif defined(__AVX2__)
    out = std::bit_cast<Reals>(_mm256_i64gather_pd(table, std::bit_cast<__m256i>(index), 8));
#else
    for (int l = 0; l < kLanes; ++l) out[l] = table[index[l]];
#endif
  }

  // Bit l set when lane l of the mask is set.
  static unsigned lane_bits(const Masks& mask) noexcept {
#if defined(__AVX512DQ__)
    return _mm512_movepi64_mask(std::bit_cast<__m512i>(mask));
#elif defined(__AVX2__) && !defined(__AVX512F__)
    return static_cast<unsigned>(_mm256_movemask_pd(std::bit_cast<__m256d>(mask)));
#else
    unsigned bits = 0;
    for (int l = 0; l < kLanes; ++l) bits |= (mask[l] != 0 ? 1u : 0u) << l;
    return bits;
#endif
  }

  // xoshiro256++ (xoshiro256.hpp) on every lane.
  void next(Words& result) noexcept {
    const Words sum = s_[0] + s_[3];
    result = ((sum << 23) | (sum >> 41)) + s_[0];
    const Words t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = (s_[3] << 45) | (s_[3] >> 19);
  }

  Xoshiro256PlusPlus lane(int l) const noexcept {
    return Xoshiro256PlusPlus(std::array<std::uint64_t, 4>{s_[0][l], s_[1][l], s_[2][l], s_[3][l]});
  }
  void set_lane(int l, const Xoshiro256PlusPlus& engine) noexcept {
    const auto& s = engine.state();
    for (int j = 0; j < 4; ++j) s_[j][l] = s[j];
  }

  Words s_[4] = {};  // s_[j][l]: word j of lane l's state
};

}  // namespace flexloop::plant::runtime::effects::ziggurat
