// SPDX-License-Identifier: BSD-3-Clause
#include "rt/latency_histogram.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace flexloop::rt {

std::int64_t nearest_rank(double q, std::int64_t n) noexcept {
  if (n <= 0) return 0;
  // The factor absorbs the rounding of q (0.99 is not exact in binary) so that q n landing on
  // an integer k gives k, not k + 1; it is far below 1/1000 for any n below 1e9.
  const double r = std::ceil(q * static_cast<double>(n) * (1.0 - 1e-13));
  if (!(r >= 1)) return 1;
  return r >= static_cast<double>(n) ? n : static_cast<std::int64_t>(r);
}

std::int64_t LatencyHistogram::bin_lower(int i) noexcept {
  if (i < kLinearLimitNs) return i;
  if (i >= kBins - 1) return kOverflowNs;
  const int j = i - static_cast<int>(kLinearLimitNs);
  const int octave = kLinearBits + j / kSubBins;
  return (std::int64_t{1} << octave) +
         static_cast<std::int64_t>(j % kSubBins) * (std::int64_t{1} << (octave - kSubBinBits));
}

std::int64_t LatencyHistogram::bin_upper(int i) noexcept {
  if (i >= kBins - 1) return std::numeric_limits<std::int64_t>::max();
  return bin_lower(i + 1) - 1;
}

void LatencyHistogram::merge(const LatencyHistogram& other) noexcept {
  if (other.count_ == 0) return;
  for (std::size_t i = 0; i < bins_.size(); ++i) bins_[i] += other.bins_[i];
  min_ = count_ ? std::min(min_, other.min_) : other.min_;
  max_ = count_ ? std::max(max_, other.max_) : other.max_;
  count_ += other.count_;
  sum_ += other.sum_;
}

void LatencyHistogram::reset() noexcept {
  bins_.fill(0);
  count_ = min_ = max_ = sum_ = 0;
}

std::int64_t LatencyHistogram::value_at_rank(std::int64_t rank) const noexcept {
  std::int64_t seen = 0;
  for (int i = 0; i < kBins; ++i) {
    seen += bins_[static_cast<std::size_t>(i)];
    if (seen >= rank) return clamp_to_range(bin_upper(i));
  }
  return max_;
}

std::int64_t LatencyHistogram::percentile(double q) const noexcept {
  if (count_ == 0) return 0;
  return value_at_rank(nearest_rank(q, count_));
}

LatencySummary LatencyHistogram::summary() const noexcept {
  LatencySummary s;
  if (count_ == 0) return s;
  const std::int64_t ranks[3] = {nearest_rank(0.5, count_), nearest_rank(0.99, count_),
                                 nearest_rank(0.999, count_)};
  std::int64_t values[3] = {max_, max_, max_};
  int next = 0;
  std::int64_t seen = 0;
  for (int i = 0; i < kBins && next < 3; ++i) {
    seen += bins_[static_cast<std::size_t>(i)];
    while (next < 3 && seen >= ranks[next]) values[next++] = clamp_to_range(bin_upper(i));
  }
  s.min = min_;
  s.p50 = values[0];
  s.p99 = values[1];
  s.p999 = values[2];
  s.max = max_;
  s.count = count_;
  return s;
}

}  // namespace flexloop::rt
