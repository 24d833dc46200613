// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Fixed-bin histogram of durations in ns (wake-up lateness, compute time, round trip), for the
// loop's latency accounting (doc/design.md §7). record() is O(1), allocation-free, lock-free and
// never throws; the bins live inside the object (about 72 KB), so make it before the loop, on
// the heap or as a member, not on a small real-time thread stack.
//
// Bins (HDR-histogram style):
//   [0, 4096) ns                      1 ns wide (exact)
//   [2^k, 2^(k+1)) ns, k = 12 ... 31  256 equal bins per octave, width 2^(k-8) ns, so a bin's
//                                     width is at most 1/256 of any value in it (< 0.39 %)
//   >= 2^32 ns (about 4.29 s)         one overflow bin
// Negative durations (a clock that ran early) fall into bin 0; min() keeps their exact value.
//
// Percentiles are nearest-rank: percentile(q) reports for the smallest true sample value v such
// that at least ceil(q * count) samples are <= v. The reported value is the upper edge of v's
// bin, clamped to [min, max]; hence, for v >= 0,
//   v <= reported <= max   and   reported - v < max(1 ns, v / 256)  (exact below 4096 ns).
// A percentile in the overflow bin reports max. min and max are exact.
#include <array>
#include <cstdint>

namespace flexloop::rt {

/// Figures of one histogram, in ns; the same order as the *_ns[5] arrays of loop_stats_t
/// (min, p50, p99, p99.9, max). All zero when count == 0.
struct LatencySummary {
  std::int64_t min = 0;
  std::int64_t p50 = 0;
  std::int64_t p99 = 0;
  std::int64_t p999 = 0;
  std::int64_t max = 0;
  std::int64_t count = 0;
};

class LatencyHistogram {
 public:
  static constexpr int kLinearBits = 12;  // 1 ns bins below 2^12 ns
  static constexpr int kSubBinBits = 8;   // 2^8 bins per octave above
  static constexpr int kTopBits = 32;     // overflow at 2^32 ns
  static constexpr std::int64_t kLinearLimitNs = std::int64_t{1} << kLinearBits;
  static constexpr std::int64_t kOverflowNs = std::int64_t{1} << kTopBits;
  static constexpr int kSubBins = 1 << kSubBinBits;
  static constexpr int kBins =
      static_cast<int>(kLinearLimitNs) + (kTopBits - kLinearBits) * kSubBins + 1;
  /// Upper bound on (reported - true) / true for a percentile at or above kLinearLimitNs.
  static constexpr double kRelativeBinError = 1.0 / kSubBins;

  /// Adds one duration. O(1); no allocation, lock or exception.
  void record(std::int64_t ns) noexcept {
    ++bins_[static_cast<std::size_t>(bin_index(ns))];
    if (count_ == 0 || ns < min_) min_ = ns;
    if (count_ == 0 || ns > max_) max_ = ns;
    ++count_;
    sum_ += ns;
  }

  /// Adds every sample of `other` (e.g. per-thread histograms into one report).
  void merge(const LatencyHistogram& other) noexcept;
  /// Forgets every sample.
  void reset() noexcept;

  std::int64_t count() const noexcept { return count_; }
  std::int64_t min() const noexcept { return count_ ? min_ : 0; }
  std::int64_t max() const noexcept { return count_ ? max_ : 0; }
  /// Exact mean (sum kept in 64 bits: fine below ~9e18 ns of total duration).
  double mean() const noexcept { return count_ ? static_cast<double>(sum_) / count_ : 0.0; }

  /// Nearest-rank percentile, q in (0, 1] (0.99 for p99); see the bound above. O(kBins).
  std::int64_t percentile(double q) const noexcept;
  /// min, p50, p99, p99.9, max and count in one pass over the bins. O(kBins), allocation-free.
  LatencySummary summary() const noexcept;

  /// Bin access, for drawing the histogram: bin i holds values in [bin_lower(i), bin_upper(i)].
  static int bin_index(std::int64_t ns) noexcept {
    if (ns < kLinearLimitNs) return ns < 0 ? 0 : static_cast<int>(ns);
    if (ns >= kOverflowNs) return kBins - 1;
    const int octave = 63 - __builtin_clzll(static_cast<unsigned long long>(ns));
    const int sub = static_cast<int>((ns >> (octave - kSubBinBits)) & (kSubBins - 1));
    return static_cast<int>(kLinearLimitNs) + (octave - kLinearBits) * kSubBins + sub;
  }
  static std::int64_t bin_lower(int i) noexcept;
  /// Largest value in bin i (the overflow bin reports INT64_MAX).
  static std::int64_t bin_upper(int i) noexcept;
  std::int64_t bin_count(int i) const noexcept { return bins_[static_cast<std::size_t>(i)]; }

 private:
  // One percentile from a cumulative walk; rank in [1, count].
  std::int64_t value_at_rank(std::int64_t rank) const noexcept;
  std::int64_t clamp_to_range(std::int64_t v) const noexcept {
    return v < min_ ? min_ : (v > max_ ? max_ : v);
  }

  std::array<std::int64_t, kBins> bins_{};
  std::int64_t count_ = 0;
  std::int64_t min_ = 0;
  std::int64_t max_ = 0;
  std::int64_t sum_ = 0;
};

/// Nearest-rank: the rank (1-based) of percentile q among n samples, ceil(q n) clamped to [1, n].
std::int64_t nearest_rank(double q, std::int64_t n) noexcept;

}  // namespace flexloop::rt
