// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The distributions of a campaign's uncertain parameters (doc/campaign.md "U.toml"), each as the
// map of a design's unit coordinate u in [0, 1) to a value by its inverse CDF, so that a design
// (random, Latin hypercube, Sobol, Saltelli) over [0, 1)^d becomes a design over the parameters.
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

namespace flexloop::campaign {

enum class DistributionKind { kUniform, kNormal, kLognormal, kTruncatedNormal };

/// One concrete parameter's distribution (the nominal value already applied).
struct Distribution {
  DistributionKind kind = DistributionKind::kUniform;
  double low = -std::numeric_limits<double>::infinity();  ///< uniform, truncated_normal: bounds
  double high = std::numeric_limits<double>::infinity();
  double mean = 0, sd = 0;  ///< normal, truncated_normal (the untruncated normal's)
  double median = 0;        ///< lognormal: exp(mu)
  double sigma_log = 0;     ///< lognormal: the standard deviation of ln X
};

/// The tails of an unbounded distribution are cut at this probability: u is clamped to
/// [kTailProbability, 1 - kTailProbability], so that every draw is finite and lies between the
/// quantiles the planning check judges (doc/campaign.md "Unphysical draws").
inline constexpr double kTailProbability = 1e-9;

/// "uniform" | "normal" | "lognormal" | "truncated_normal"; std::invalid_argument otherwise.
DistributionKind distribution_kind_from_name(const std::string& name);
std::string distribution_name(DistributionKind kind);

/// The value of `d` at unit coordinate u in [0, 1): its inverse CDF (quantile function), the
/// unbounded tails cut at kTailProbability.
double inverse_cdf(const Distribution& d, double u);

/// The smallest and the largest value a draw can take (the quantiles at the cut tails).
double lowest_draw(const Distribution& d);
double highest_draw(const Distribution& d);

/// The lognormal's sigma of ln X for a relative standard deviation r = sd(X) / mean(X):
/// exp(sigma^2) - 1 = r^2.
double lognormal_sigma_from_relative_sd(double relative_sd);

/// {"distribution": name, and its numbers} (the plan's record of one concrete parameter).
nlohmann::json to_json(const Distribution& d);
Distribution distribution_from_json(const nlohmann::json& j);

}  // namespace flexloop::campaign
