// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The campaign's estimators (doc/campaign_statistics.md has the formulas and the rules):
// distribution-free quantile intervals from order statistics, the exact (Clopper-Pearson)
// binomial interval, and Sobol indices from a Saltelli design with bootstrap intervals.
#include <cstdint>
#include <vector>

namespace flexloop::campaign {

struct Interval {
  double estimate, lo, hi;
};

/// The p-quantile of a sample: estimate = x_(k), k = max(1, ceil(n p)) (the ECDF's inverse);
/// [lo, hi] = [x_(l), x_(u)] with the ranks 0 <= l < u <= n + 1 (x_(0) = -inf, x_(n+1) = +inf)
/// of smallest u - l such that P(l <= B < u) >= the requested confidence, B ~ Binomial(n, p),
/// the tails P(B < l) and P(B >= u) as equal as possible among those. `confidence` is the
/// achieved P(l <= B < u): the coverage for a continuous distribution. n too small for finite
/// ends: lo = -inf and/or hi = +inf (an infinite end is the honest answer).
struct QuantileInterval {
  double p, estimate, lo, hi, confidence;
  long lo_rank, hi_rank;  ///< l and u (1-based ranks; 0 and n + 1 are the infinite ends)
};
/// xs: any order, +-inf allowed (an order statistic like any other), NaN refused
/// (std::invalid_argument); 0 < p < 1; 0 < confidence < 1.
/// An empty sample: estimate NaN, lo = -inf, hi = +inf, confidence 1.
QuantileInterval quantile_interval(std::vector<double> xs, double p, double confidence = 0.95);

/// The order-statistic ranks (l, u) of quantile_interval for a sample of n and its coverage.
struct RankInterval {
  long lo_rank, hi_rank;
  double coverage;
};
RankInterval quantile_ranks(long n, double p, double confidence);

/// Clopper-Pearson (exact) interval of a binomial proportion failures / n:
/// lo = Beta^-1(alpha/2; k, n-k+1) (0 for k = 0), hi = Beta^-1(1-alpha/2; k+1, n-k) (1 for k = n).
/// n = 0: estimate NaN, [0, 1].
Interval clopper_pearson(long failures, long n, double confidence = 0.95);

struct SobolIndex {
  Interval first, total;
  bool first_holds_zero, total_holds_zero;
};

/// First (Saltelli 2010) and total (Jansen 1999) Sobol indices from outputs y in the Saltelli
/// layout (index b*(d+2) + j: A_b, B_b, A_b with column i from B_b), one per parameter, with
/// bootstrap percentile intervals (`bootstrap` resamplings of the n base rows, drawn with
/// CounterStream(seed, .)). y must be finite and of size n*(d+2) (std::invalid_argument).
/// Constant outputs (zero variance): NaN indices, not marked.
std::vector<SobolIndex> sobol_indices(const std::vector<double>& y, long n, int d,
                                      int bootstrap = 500, std::uint64_t seed = 1,
                                      double confidence = 0.95);

}  // namespace flexloop::campaign
