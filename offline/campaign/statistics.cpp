// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/statistics.hpp"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/special_functions/beta.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

#include "offline/campaign/counter_random.hpp"

namespace flexloop::campaign {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_confidence(double confidence, const char* who) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument(std::string(who) + ": confidence " + std::to_string(confidence) +
                                " outside (0, 1)");
}

// Order statistic x_(rank) of sorted xs, 1-based; ranks 0 and n + 1 are -inf and +inf.
double order_statistic(const std::vector<double>& sorted, long rank) {
  if (rank <= 0) return -kInf;
  if (rank > static_cast<long>(sorted.size())) return kInf;
  return sorted[static_cast<std::size_t>(rank - 1)];
}

RankInterval compute_ranks(long n, double p, double confidence) {
  const boost::math::binomial_distribution<double> binomial(static_cast<double>(n), p);
  // below[l] = P(B < l), at_or_above[u] = P(B >= u), for l, u in 0..n+1.
  const auto size = static_cast<std::size_t>(n + 2);
  std::vector<double> below(size, 0.0), at_or_above(size, 0.0);
  at_or_above[0] = 1.0;
  for (long k = 1; k <= n; ++k) {
    below[static_cast<std::size_t>(k)] = boost::math::cdf(binomial, static_cast<double>(k - 1));
    at_or_above[static_cast<std::size_t>(k)] =
        boost::math::cdf(boost::math::complement(binomial, static_cast<double>(k - 1)));
  }
  below[size - 1] = 1.0;
  const auto coverage = [&](long l, long u) {
    return 1.0 - below[static_cast<std::size_t>(l)] - at_or_above[static_cast<std::size_t>(u)];
  };
  // The narrowest pair with l_min <= l < u <= u_max, tails as equal as possible; for each l the
  // smallest u with enough coverage (it grows with l). {0, 0, 0} when there is none.
  const auto narrowest = [&](long l_min, long u_max) {
    RankInterval best{0, 0, 0.0};
    double best_imbalance = kInf;
    for (long l = l_min, u = l_min + 1; l < u_max; ++l) {
      u = std::max(u, l + 1);
      while (u <= u_max && coverage(l, u) < confidence) ++u;
      if (u > u_max) break;  // no u for this l, nor for any larger l
      const double imbalance =
          std::abs(below[static_cast<std::size_t>(l)] - at_or_above[static_cast<std::size_t>(u)]);
      const long span = u - l, best_span = best.hi_rank - best.lo_rank;
      if (best_span == 0 || span < best_span || (span == best_span && imbalance < best_imbalance))
        best = {l, u, coverage(l, u)}, best_imbalance = imbalance;
    }
    return best;
  };
  // Finite ends when n allows them; else an infinite end (rank 0 or n + 1), or two.
  if (const RankInterval finite = narrowest(1, n); finite.hi_rank > 0) return finite;
  return narrowest(0, n + 1);
}

}  // namespace

RankInterval quantile_ranks(long n, double p, double confidence) {
  if (n < 0) throw std::invalid_argument("quantile_ranks: n < 0");
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument("quantile_ranks: p = " + std::to_string(p) + " outside (0, 1)");
  check_confidence(confidence, "quantile_ranks");
  if (n == 0) return {0, 1, 1.0};
  // The ranks depend on (n, p, confidence) only: a report asks for the same ones many times.
  thread_local std::map<std::tuple<long, double, double>, RankInterval> known;
  const auto key = std::make_tuple(n, p, confidence);
  if (const auto it = known.find(key); it != known.end()) return it->second;
  const RankInterval ranks = compute_ranks(n, p, confidence);
  if (known.size() > 4096) known.clear();
  known.emplace(key, ranks);
  return ranks;
}

QuantileInterval quantile_interval(std::vector<double> xs, double p, double confidence) {
  // An infinity is an order statistic like any other (an unbounded margin: the best machine);
  // NaN has no rank.
  for (double x : xs)
    if (std::isnan(x)) throw std::invalid_argument("quantile_interval: a value is NaN");
  const auto n = static_cast<long>(xs.size());
  const RankInterval ranks = quantile_ranks(n, p, confidence);
  std::sort(xs.begin(), xs.end());
  const long k = std::max(1L, static_cast<long>(std::ceil(static_cast<double>(n) * p)));
  const double estimate = n == 0 ? kNaN : order_statistic(xs, k);
  return {p,
          estimate,
          order_statistic(xs, ranks.lo_rank),
          order_statistic(xs, ranks.hi_rank),
          ranks.coverage,
          ranks.lo_rank,
          ranks.hi_rank};
}

Interval clopper_pearson(long failures, long n, double confidence) {
  check_confidence(confidence, "clopper_pearson");
  if (n < 0 || failures < 0 || failures > n)
    throw std::invalid_argument("clopper_pearson: " + std::to_string(failures) + " of " +
                                std::to_string(n));
  if (n == 0) return {kNaN, 0.0, 1.0};
  const double alpha = 1.0 - confidence;
  const auto k = static_cast<double>(failures), m = static_cast<double>(n);
  const double lo = failures == 0 ? 0.0 : boost::math::ibeta_inv(k, m - k + 1.0, alpha / 2.0);
  const double hi = failures == n ? 1.0 : boost::math::ibeta_inv(k + 1.0, m - k, 1.0 - alpha / 2.0);
  return {k / m, lo, hi};
}

namespace {

struct FirstAndTotal {
  std::vector<double> first, total;
};

// The estimators over the base rows `rows` (a row may repeat: a bootstrap resample). Outputs are
// centred on the mean m of all the rows' outputs (as OpenTURNS does, for stability);
// V = sum (yA - mean yA)^2 / (N - 1);
// S_i = sum (yB - m)(yE_i - yA) / (N - 1) / V   (Saltelli et al. 2010, table 2 (b));
// T_i = sum (yA - yE_i)^2 / (2 N) / V           (Jansen 1999; Saltelli et al. 2010, table 2 (f)).
FirstAndTotal estimate_indices(const std::vector<double>& y, int d, const std::vector<long>& rows) {
  const long stride = d + 2L;
  const auto at = [&](long row, long j) { return y[static_cast<std::size_t>(row * stride + j)]; };
  const auto count = static_cast<double>(rows.size());
  double m = 0.0, mean_a = 0.0;
  for (long r : rows) {
    for (long j = 0; j < stride; ++j) m += at(r, j);
    mean_a += at(r, 0);
  }
  m /= count * static_cast<double>(stride);
  mean_a /= count;
  double variance = 0.0;
  for (long r : rows) variance += (at(r, 0) - mean_a) * (at(r, 0) - mean_a);
  variance /= count - 1.0;
  FirstAndTotal out{std::vector<double>(static_cast<std::size_t>(d), kNaN),
                    std::vector<double>(static_cast<std::size_t>(d), kNaN)};
  if (!(variance > 0.0)) return out;
  for (int i = 0; i < d; ++i) {
    double first = 0.0, total = 0.0;
    for (long r : rows) {
      const double ya = at(r, 0), yb = at(r, 1), ye = at(r, 2 + i);
      first += (yb - m) * (ye - ya);
      total += (ya - ye) * (ya - ye);
    }
    out.first[static_cast<std::size_t>(i)] = first / (count - 1.0) / variance;
    out.total[static_cast<std::size_t>(i)] = total / (2.0 * count) / variance;
  }
  return out;
}

// Percentile interval of bootstrap replicates: the ECDF's inverse at alpha/2 and 1 - alpha/2.
// Replicates of zero variance (NaN) are left out.
std::pair<double, double> percentile_interval(std::vector<double> replicates, double confidence) {
  replicates.erase(std::remove_if(replicates.begin(), replicates.end(),
                                  [](double r) { return !std::isfinite(r); }),
                   replicates.end());
  if (replicates.empty()) return {kNaN, kNaN};
  std::sort(replicates.begin(), replicates.end());
  const auto b = static_cast<double>(replicates.size());
  const double alpha = 1.0 - confidence;
  const auto rank = [&](double q) {
    return std::clamp(static_cast<long>(std::ceil(b * q)), 1L, static_cast<long>(b));
  };
  return {replicates[static_cast<std::size_t>(rank(alpha / 2.0) - 1)],
          replicates[static_cast<std::size_t>(rank(1.0 - alpha / 2.0) - 1)]};
}

}  // namespace

std::vector<SobolIndex> sobol_indices(const std::vector<double>& y, long n, int d, int bootstrap,
                                      std::uint64_t seed, double confidence) {
  check_confidence(confidence, "sobol_indices");
  if (n < 2 || d < 1 || bootstrap < 1)
    throw std::invalid_argument("sobol_indices: need n >= 2, d >= 1 and bootstrap >= 1");
  if (static_cast<long>(y.size()) != n * (d + 2L))
    throw std::invalid_argument(
        "sobol_indices: " + std::to_string(y.size()) + " outputs, " + std::to_string(n * (d + 2L)) +
        " expected for n = " + std::to_string(n) + ", d = " + std::to_string(d));
  for (double v : y)
    if (!std::isfinite(v)) throw std::invalid_argument("sobol_indices: an output is not finite");
  std::vector<long> rows(static_cast<std::size_t>(n));
  for (long r = 0; r < n; ++r) rows[static_cast<std::size_t>(r)] = r;
  const FirstAndTotal point = estimate_indices(y, d, rows);
  // Replicate k resamples the n base rows with CounterStream(seed, k).
  const auto dd = static_cast<std::size_t>(d);
  std::vector<std::vector<double>> first(dd), total(dd);
  for (int k = 0; k < bootstrap; ++k) {
    CounterStream stream(seed, static_cast<std::uint64_t>(k));
    for (long& r : rows) r = static_cast<long>(stream.below(static_cast<std::uint64_t>(n)));
    const FirstAndTotal replicate = estimate_indices(y, d, rows);
    for (std::size_t i = 0; i < dd; ++i) {
      first[i].push_back(replicate.first[i]);
      total[i].push_back(replicate.total[i]);
    }
  }
  std::vector<SobolIndex> out;
  for (std::size_t i = 0; i < dd; ++i) {
    SobolIndex index{{point.first[i], kNaN, kNaN}, {point.total[i], kNaN, kNaN}, false, false};
    if (std::isfinite(point.first[i])) {
      std::tie(index.first.lo, index.first.hi) = percentile_interval(first[i], confidence);
      std::tie(index.total.lo, index.total.hi) = percentile_interval(total[i], confidence);
    }
    index.first_holds_zero = index.first.lo <= 0.0 && 0.0 <= index.first.hi;
    index.total_holds_zero = index.total.lo <= 0.0 && 0.0 <= index.total.hi;
    out.push_back(index);
  }
  return out;
}

}  // namespace flexloop::campaign
