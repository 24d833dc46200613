// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Subset simulation (Au & Beck 2001, "Estimation of small failure probabilities in high
// dimensions by subset simulation", Probabilistic Engineering Mechanics 16(4)) of a small
// probability P(g(Z) >= 0), Z ~ N(0, I_d): a rare event as a product of conditional events
// {g >= b_1} ⊃ {g >= b_2} ⊃ ... ⊃ {g >= 0} each of probability about p0, each level sampled from
// the previous one's best p0 N samples by modified Metropolis chains (doc/campaign_statistics.md,
// "Subset simulation").
//
//   level 0   N independent standard normal points.
//   level j   b_j = the (p0 N)-th largest g of level j - 1 (its p0 N best are the seeds); when it
//   is
//             >= 0 the failures are frequent enough to count: stop. Otherwise each seed starts a
//             chain of 1/p0 states (the seed and 1/p0 - 1 new ones), N states in all. A step
//             proposes every coordinate by itself, xi_i ~ U(z_i - w, z_i + w), kept with
//             probability min(1, phi(xi_i) / phi(z_i)) (the modified Metropolis of Au & Beck), then
//             moves to the candidate if g(candidate) >= b_j, else stays. A candidate equal to the
//             current state (no coordinate kept) costs no evaluation.
//   estimate  P = p_1 ... p_m * (failures of level m) / N, p_j = #(g >= b_j among level j-1) / N
//             (= p0 without ties).
//   CoV       delta^2 = sum_j delta_j^2, delta_j^2 = (1 - P_j) / (N P_j) (1 + gamma_j), gamma_0 = 0
//             (independent points), gamma_j = 2 sum_{k=1}^{Ns-1} (1 - k / Ns) rho_j(k) from the
//             correlation of the indicator along the chains (Au & Beck eq. 29). The sum leaves out
//             the correlation between levels (their seeds are shared): it is Au & Beck's lower
//             bound of the CoV, the one OpenTURNS reports too.
//   interval  [P exp(-1.96 s), P exp(+1.96 s)], s^2 = ln(1 + delta^2): the lognormal with that CoV,
//             an approximate, asymptotic 95 % interval (no exact coverage; subset simulation's
//             estimate is also biased by O(1/N)). With no failure in the last level allowed
//             (max_levels reached): estimate 0, lo 0, hi = p_1 ... p_m (the probability of the
//             last level's domain, which holds the failure domain), cov NaN.
//
// The random numbers are counter-based (offline/campaign/counter_random.hpp) keyed by (seed,
// level, chain, step, coordinate): the result depends on the seed alone, never on the order or
// the grouping in which a batch's points are evaluated.
#include <cstdint>
#include <functional>
#include <vector>

namespace flexloop::campaign {

/// Points in the standard normal space, one vector of d coordinates each.
using NormalPoints = std::vector<std::vector<double>>;
/// g of every point of a batch, in order (the points of a batch are independent: they may be
/// evaluated in parallel). Failure is g >= 0; +inf is allowed (a point that fails the most), NaN
/// is not (std::invalid_argument from subset_simulation).
using BatchLimitState = std::function<std::vector<double>(const NormalPoints&)>;

struct SubsetSettings {
  long per_level = 1000;  ///< N; N p0 and 1 / p0 must be whole numbers
  double p0 = 0.1;        ///< the conditional probability of each level
  int max_levels = 10;    ///< conditional levels after level 0 (p0^10 = 1e-10 at p0 = 0.1)
  double proposal_half_width = 1.0;  ///< w of the uniform proposal, in standard deviations
  std::uint64_t seed = 1;
};

struct SubsetLevel;
/// Told each level as it is done (progress).
using SubsetLevelDone = std::function<void(int level, const SubsetLevel&)>;

struct SubsetLevel {
  double threshold = 0;   ///< b of the event this level's samples are counted for (0: last)
  double fraction = 0;    ///< P_j: the share of this level's N samples with g >= threshold
  long evaluations = 0;   ///< g evaluated at this level (N at level 0)
  double acceptance = 0;  ///< share of chain steps that moved (NaN at level 0)
  double gamma = 0;       ///< chain correlation factor (0 at level 0)
  double cov = 0;         ///< delta_j
};

struct SubsetResult {
  double estimate = 0, cov = 0, lo = 0, hi = 0;
  long evaluations = 0;
  bool reached_failure = true;  ///< false: max_levels reached with fewer than p0 N failures
  std::vector<SubsetLevel> levels;
};

/// @throws std::invalid_argument for settings outside their ranges (N < 2, p0 not in (0, 0.5],
/// N p0 or 1/p0 not whole, d < 1, w <= 0, max_levels < 0), a batch answer of the wrong size or
/// a NaN g.
SubsetResult subset_simulation(int dimension, const BatchLimitState& g, const SubsetSettings& s,
                               const SubsetLevelDone& level_done = {});

/// The chain correlation factor gamma = 2 sum_{k=1}^{Ns-1} (1 - k/Ns) R(k) / R(0) of indicator
/// values laid out chain after chain (chains of equal length Ns), R(k) the lag-k covariance
/// pooled over the chains about their pooled mean (Au & Beck 2001, eq. 25-29). 0 when the
/// indicator is constant.
double chain_correlation_factor(const std::vector<bool>& indicator, long chains);

/// The lognormal interval of an estimate with coefficient of variation `cov`, at the two-sided
/// normal quantile z (1.96 for 95 %): [p e^{-z s}, p e^{z s}], s^2 = ln(1 + cov^2).
struct LognormalInterval {
  double lo, hi;
};
LognormalInterval lognormal_interval(double estimate, double cov, double z = 1.959963984540054);

}  // namespace flexloop::campaign
