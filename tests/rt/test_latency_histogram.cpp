// SPDX-License-Identifier: BSD-3-Clause
// rt/latency_histogram.hpp against sorted reference data: min/max/count exact, nearest-rank
// percentiles exact below 4096 ns and within the stated 1/256 relative bin error above, never
// above max; bins tile the range; merge equals recording everything; reset forgets.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "rt/latency_histogram.hpp"

using flexloop::rt::LatencyHistogram;

namespace {

// Nearest rank of the fraction num/den among n samples, in integers: ceil(num n / den).
std::int64_t reference_rank(std::int64_t num, std::int64_t den, std::int64_t n) {
  return std::max<std::int64_t>(1, (num * n + den - 1) / den);
}

// Latency-like data: a dense body of microseconds, a log-uniform tail to seconds, some exact
// small values and a few beyond the overflow edge.
std::vector<std::int64_t> reference_data(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::lognormal_distribution<double> body(std::log(20'000.0), 0.4);
  std::uniform_real_distribution<double> log_tail(std::log(1e3), std::log(5e9));
  std::uniform_int_distribution<std::int64_t> small(0, 5000);
  std::vector<std::int64_t> v(n);
  for (auto& x : v) {
    const double u = std::uniform_real_distribution<double>(0, 1)(rng);
    if (u < 0.8)
      x = static_cast<std::int64_t>(body(rng));
    else if (u < 0.9)
      x = small(rng);
    else
      x = static_cast<std::int64_t>(std::exp(log_tail(rng)));
  }
  return v;
}

void check_percentile(const LatencyHistogram& h, const std::vector<std::int64_t>& sorted,
                      std::int64_t reported, std::int64_t num, std::int64_t den) {
  const auto n = static_cast<std::int64_t>(sorted.size());
  const std::int64_t truth = sorted[static_cast<std::size_t>(reference_rank(num, den, n) - 1)];
  INFO("q = " << num << "/" << den << ", true " << truth << " ns, reported " << reported);
  CHECK(reported >= truth);
  CHECK(reported <= h.max());
  if (truth < LatencyHistogram::kLinearLimitNs)
    CHECK(reported == truth);
  else if (truth < LatencyHistogram::kOverflowNs)
    CHECK(static_cast<double>(reported - truth) <
          LatencyHistogram::kRelativeBinError * static_cast<double>(truth));
  else
    CHECK(reported == h.max());
}

}  // namespace

TEST_CASE("histogram bins tile 0 to 2^32 ns without gaps, each at most 1/256 of its values wide") {
  for (int i = 0; i + 1 < LatencyHistogram::kBins; ++i) {
    const std::int64_t lo = LatencyHistogram::bin_lower(i), hi = LatencyHistogram::bin_upper(i);
    REQUIRE(LatencyHistogram::bin_index(lo) == i);
    REQUIRE(LatencyHistogram::bin_index(hi) == i);
    REQUIRE(LatencyHistogram::bin_lower(i + 1) == hi + 1);
    if (lo >= LatencyHistogram::kLinearLimitNs)
      REQUIRE(static_cast<double>(hi - lo + 1) <=
              LatencyHistogram::kRelativeBinError * static_cast<double>(lo));
    else
      REQUIRE(hi == lo);
  }
  CHECK(LatencyHistogram::bin_upper(LatencyHistogram::kBins - 2) ==
        LatencyHistogram::kOverflowNs - 1);
  CHECK(LatencyHistogram::bin_index(LatencyHistogram::kOverflowNs) == LatencyHistogram::kBins - 1);
  CHECK(LatencyHistogram::bin_index(-5) == 0);
}

TEST_CASE("histogram percentiles match sorted reference data within the stated bound") {
  for (const std::size_t n :
       {std::size_t{1}, std::size_t{7}, std::size_t{1000}, std::size_t{100'003}}) {
    const auto data = reference_data(n, 42 + n);
    auto h = std::make_unique<LatencyHistogram>();
    for (auto x : data) h->record(x);
    auto sorted = data;
    std::sort(sorted.begin(), sorted.end());
    INFO("n = " << n);
    CHECK(h->count() == static_cast<std::int64_t>(n));
    CHECK(h->min() == sorted.front());
    CHECK(h->max() == sorted.back());

    const auto s = h->summary();
    CHECK(s.count == h->count());
    CHECK(s.min == sorted.front());
    CHECK(s.max == sorted.back());
    check_percentile(*h, sorted, s.p50, 50, 100);
    check_percentile(*h, sorted, s.p99, 99, 100);
    check_percentile(*h, sorted, s.p999, 999, 1000);
    CHECK(h->percentile(0.5) == s.p50);
    CHECK(h->percentile(0.99) == s.p99);
    CHECK(h->percentile(0.999) == s.p999);
    for (std::int64_t num : {1, 10, 250, 500, 750, 900, 990, 999, 1000})
      check_percentile(*h, sorted, h->percentile(static_cast<double>(num) / 1000.0), num, 1000);
  }
}

TEST_CASE("histogram percentiles are exact for values below 4096 ns") {
  auto h = std::make_unique<LatencyHistogram>();
  std::vector<std::int64_t> v;
  for (std::int64_t x = 0; x < 4000; x += 3) v.push_back(x);
  std::shuffle(v.begin(), v.end(), std::mt19937(1));
  for (auto x : v) h->record(x);
  std::sort(v.begin(), v.end());
  const auto n = static_cast<std::int64_t>(v.size());
  CHECK(h->summary().p50 == v[static_cast<std::size_t>(reference_rank(1, 2, n) - 1)]);
  CHECK(h->summary().p99 == v[static_cast<std::size_t>(reference_rank(99, 100, n) - 1)]);
}

TEST_CASE("histogram merge equals recording every sample in one, reset forgets") {
  const auto data = reference_data(20'000, 7);
  auto all = std::make_unique<LatencyHistogram>();
  auto a = std::make_unique<LatencyHistogram>();
  auto b = std::make_unique<LatencyHistogram>();
  for (std::size_t i = 0; i < data.size(); ++i) {
    all->record(data[i]);
    (i % 3 ? *a : *b).record(data[i]);
  }
  auto empty = std::make_unique<LatencyHistogram>();
  a->merge(*empty);
  empty->merge(*a);  // merging into an empty histogram takes min and max over
  CHECK(empty->min() == a->min());
  a->merge(*b);
  for (int i = 0; i < LatencyHistogram::kBins; ++i) REQUIRE(a->bin_count(i) == all->bin_count(i));
  const auto sa = a->summary(), sall = all->summary();
  CHECK(sa.min == sall.min);
  CHECK(sa.p50 == sall.p50);
  CHECK(sa.p99 == sall.p99);
  CHECK(sa.p999 == sall.p999);
  CHECK(sa.max == sall.max);
  CHECK(sa.count == sall.count);
  CHECK(a->mean() == Approx(all->mean()).epsilon(1e-12));

  a->reset();
  CHECK(a->count() == 0);
  const auto z = a->summary();
  CHECK((z.min == 0 && z.p50 == 0 && z.p99 == 0 && z.p999 == 0 && z.max == 0 && z.count == 0));
  a->record(5);
  CHECK((a->min() == 5 && a->max() == 5 && a->percentile(0.5) == 5));
}

TEST_CASE("negative durations count in the lowest bin, min keeps the exact value") {
  auto h = std::make_unique<LatencyHistogram>();
  h->record(-250);
  h->record(10);
  h->record(20);
  CHECK(h->min() == -250);
  CHECK(h->bin_count(0) == 1);
  CHECK(h->percentile(0.5) == 10);
  CHECK(h->percentile(0.01) == 0);  // the bin's upper edge: clamped into [min, max]
}
