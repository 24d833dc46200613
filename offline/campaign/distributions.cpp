// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/distributions.hpp"

#include <algorithm>
#include <boost/math/distributions/lognormal.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <stdexcept>

namespace flexloop::campaign {

namespace {

double clamp_tails(double u) {
  return std::clamp(u, kTailProbability, 1 - kTailProbability);
}

// The truncated normal's quantile: x = mean + sd * Phi^-1(Phi(a) + u (Phi(b) - Phi(a))) with the
// standardised bounds a, b; in the upper tail by the complements, so that a bound far above the
// mean keeps its precision.
double truncated_normal_quantile(const Distribution& d, double u) {
  const boost::math::normal_distribution<double> standard(0.0, 1.0);
  const double a = (d.low - d.mean) / d.sd, b = (d.high - d.mean) / d.sd;
  // An unbounded side is cut at its 1e-9 quantile, as the normal's (u = 0 would map to -inf).
  if (!std::isfinite(a)) u = std::max(u, kTailProbability);
  if (!std::isfinite(b)) u = std::min(u, 1 - kTailProbability);
  double z;
  if (a > 0) {
    const double qa = std::isfinite(a) ? cdf(complement(standard, a)) : 1.0;
    const double qb = std::isfinite(b) ? cdf(complement(standard, b)) : 0.0;
    z = quantile(complement(standard, qa - u * (qa - qb)));
  } else {
    const double pa = std::isfinite(a) ? cdf(standard, a) : 0.0;
    const double pb = std::isfinite(b) ? cdf(standard, b) : 1.0;
    const double p = pa + u * (pb - pa);
    z = quantile(standard, std::clamp(p, std::numeric_limits<double>::min(), 1.0));
  }
  return std::clamp(d.mean + d.sd * z, d.low, d.high);
}

}  // namespace

DistributionKind distribution_kind_from_name(const std::string& name) {
  if (name == "uniform") return DistributionKind::kUniform;
  if (name == "normal") return DistributionKind::kNormal;
  if (name == "lognormal") return DistributionKind::kLognormal;
  if (name == "truncated_normal") return DistributionKind::kTruncatedNormal;
  throw std::invalid_argument("distribution '" + name +
                              "' is not one of uniform, normal, lognormal, truncated_normal");
}

std::string distribution_name(DistributionKind kind) {
  switch (kind) {
    case DistributionKind::kUniform:
      return "uniform";
    case DistributionKind::kNormal:
      return "normal";
    case DistributionKind::kLognormal:
      return "lognormal";
    case DistributionKind::kTruncatedNormal:
      return "truncated_normal";
  }
  return "?";
}

double inverse_cdf(const Distribution& d, double u) {
  switch (d.kind) {
    case DistributionKind::kUniform:
      return d.low + u * (d.high - d.low);
    case DistributionKind::kNormal:
      return quantile(boost::math::normal_distribution<double>(d.mean, d.sd), clamp_tails(u));
    case DistributionKind::kLognormal:
      return quantile(boost::math::lognormal_distribution<double>(std::log(d.median), d.sigma_log),
                      clamp_tails(u));
    case DistributionKind::kTruncatedNormal:
      return truncated_normal_quantile(d, u);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double lowest_draw(const Distribution& d) {
  return d.kind == DistributionKind::kUniform ? d.low : inverse_cdf(d, 0.0);
}

double highest_draw(const Distribution& d) {
  // The uniform's supremum (u < 1 never reaches it, but it bounds every draw).
  return d.kind == DistributionKind::kUniform ? d.high : inverse_cdf(d, 1 - kTailProbability);
}

double lognormal_sigma_from_relative_sd(double relative_sd) {
  return std::sqrt(std::log1p(relative_sd * relative_sd));
}

nlohmann::json to_json(const Distribution& d) {
  nlohmann::json j{{"distribution", distribution_name(d.kind)}};
  switch (d.kind) {
    case DistributionKind::kUniform:
      j["low"] = d.low, j["high"] = d.high;
      break;
    case DistributionKind::kNormal:
      j["mean"] = d.mean, j["sd"] = d.sd;
      break;
    case DistributionKind::kLognormal:
      j["median"] = d.median, j["sigma_log"] = d.sigma_log;
      break;
    case DistributionKind::kTruncatedNormal:
      j["mean"] = d.mean, j["sd"] = d.sd;
      // JSON has no infinity: an open side is null.
      j["low"] = std::isfinite(d.low) ? nlohmann::json(d.low) : nlohmann::json();
      j["high"] = std::isfinite(d.high) ? nlohmann::json(d.high) : nlohmann::json();
      break;
  }
  return j;
}

Distribution distribution_from_json(const nlohmann::json& j) {
  Distribution d;
  d.kind = distribution_kind_from_name(j.at("distribution").get<std::string>());
  auto bound = [&](const char* key, double open) {
    return j.contains(key) && !j.at(key).is_null() ? j.at(key).get<double>() : open;
  };
  const double inf = std::numeric_limits<double>::infinity();
  d.low = bound("low", -inf);
  d.high = bound("high", inf);
  d.mean = bound("mean", 0.0);
  d.sd = bound("sd", 0.0);
  d.median = bound("median", 0.0);
  d.sigma_log = bound("sigma_log", 0.0);
  return d;
}

}  // namespace flexloop::campaign
