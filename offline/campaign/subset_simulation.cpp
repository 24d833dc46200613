// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/subset_simulation.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "offline/campaign/counter_random.hpp"

namespace flexloop::campaign {

namespace {

// A level's random numbers: stream (level, point or chain), so that no two draws share a key.
std::uint64_t stream_key(int level, long index) {
  return (static_cast<std::uint64_t>(level) << 40) ^ static_cast<std::uint64_t>(index);
}

// A uniform in the open (0, 1): the 53 bits' midpoint, never 0 (whose normal quantile is -inf).
double open_unit(std::uint64_t bits) {
  return (static_cast<double>(bits >> 11) + 0.5) * 0x1p-53;
}

double standard_normal_quantile(double u) {
  return quantile(boost::math::normal_distribution<double>(0.0, 1.0), u);
}

bool whole(double x) {
  return std::abs(x - std::round(x)) < 1e-9 * std::max(1.0, std::abs(x));
}

void require_valid(int dimension, const SubsetSettings& s) {
  auto refuse = [](const std::string& what) {
    throw std::invalid_argument("subset_simulation: " + what);
  };
  if (dimension < 1) refuse("the dimension must be at least 1");
  if (!(s.p0 > 0 && s.p0 <= 0.5)) refuse("p0 must lie in (0, 0.5]");
  if (s.per_level < 2) refuse("at least 2 samples per level");
  if (!whole(1 / s.p0) || !whole(s.p0 * static_cast<double>(s.per_level)))
    refuse("1/p0 and p0 N must be whole numbers (p0 = " + std::to_string(s.p0) +
           ", N = " + std::to_string(s.per_level) + ")");
  if (!(s.proposal_half_width > 0)) refuse("the proposal's half-width must be > 0");
  if (s.max_levels < 0) refuse("max_levels must be >= 0");
}

std::vector<double> evaluate(const BatchLimitState& g, const NormalPoints& points) {
  if (points.empty()) return {};
  std::vector<double> values = g(points);
  if (values.size() != points.size())
    throw std::invalid_argument("subset_simulation: the limit state answered " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(points.size()) + " points");
  if (std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); }))
    throw std::invalid_argument("subset_simulation: the limit state answered NaN");
  return values;
}

// A level's N points and their g, chain after chain (level 0: independent points).
struct LevelSamples {
  NormalPoints z;
  std::vector<double> g;
  long evaluations = 0, moves = 0, steps = 0;
};

LevelSamples independent_level(int d, const BatchLimitState& g, const SubsetSettings& s) {
  LevelSamples level;
  level.z.assign(static_cast<std::size_t>(s.per_level), std::vector<double>(d));
  for (long k = 0; k < s.per_level; ++k) {
    CounterStream random(s.seed, stream_key(0, k));
    for (double& x : level.z[k]) x = standard_normal_quantile(open_unit(random.next()));
  }
  level.g = evaluate(g, level.z);
  level.evaluations = s.per_level;
  return level;
}

// The indices of the `count` largest g (ties: the lower index first), in ascending index order.
std::vector<long> best_indices(const std::vector<double>& g, long count) {
  std::vector<long> order(g.size());
  std::iota(order.begin(), order.end(), 0L);
  std::stable_sort(order.begin(), order.end(), [&](long a, long b) { return g[a] > g[b]; });
  order.resize(static_cast<std::size_t>(count));
  std::sort(order.begin(), order.end());
  return order;
}

// One modified Metropolis candidate: each coordinate proposed by itself from U(x - w, x + w) and
// kept with probability min(1, phi(xi) / phi(x)), its draws keyed (chain, step, coordinate).
std::vector<double> candidate(const std::vector<double>& x, const SubsetSettings& s, int level,
                              long chain, long step) {
  std::vector<double> out = x;
  const std::uint64_t stream = stream_key(level, chain);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto key = 2 * (static_cast<std::uint64_t>(step) * x.size() + i);
    const double xi =
        x[i] + s.proposal_half_width * (2 * unit_from_bits(counter_bits(s.seed, stream, key)) - 1);
    const double ratio = std::exp(0.5 * (x[i] * x[i] - xi * xi));
    if (unit_from_bits(counter_bits(s.seed, stream, key + 1)) < ratio) out[i] = xi;
  }
  return out;
}

// Level `level` from the previous one's seeds: one chain of Ns states per seed, each step of all
// chains one batch (the candidates that moved at all), a move kept when g >= threshold.
LevelSamples chain_level(const LevelSamples& previous, const std::vector<long>& seeds,
                         double threshold, int level, const BatchLimitState& g,
                         const SubsetSettings& s) {
  const long chains = static_cast<long>(seeds.size());
  const long length = s.per_level / chains;
  LevelSamples out;
  out.z.resize(static_cast<std::size_t>(s.per_level));
  out.g.resize(static_cast<std::size_t>(s.per_level));
  for (long c = 0; c < chains; ++c) {
    out.z[c * length] = previous.z[seeds[c]];
    out.g[c * length] = previous.g[seeds[c]];
  }
  for (long step = 1; step < length; ++step) {
    NormalPoints batch;
    std::vector<long> batch_chain;
    for (long c = 0; c < chains; ++c) {
      const long at = c * length + step;
      out.z[at] = out.z[at - 1];
      out.g[at] = out.g[at - 1];
      std::vector<double> next = candidate(out.z[at], s, level, c, step);
      if (next == out.z[at]) continue;  // nothing proposed was kept: the chain stays, unevaluated
      batch.push_back(std::move(next));
      batch_chain.push_back(c);
    }
    const std::vector<double> values = evaluate(g, batch);
    out.evaluations += static_cast<long>(batch.size());
    for (std::size_t b = 0; b < batch.size(); ++b) {
      if (!(values[b] >= threshold)) continue;
      const long at = batch_chain[b] * length + step;
      out.z[at] = std::move(batch[b]);
      out.g[at] = values[b];
      ++out.moves;
    }
    out.steps += chains;
  }
  return out;
}

// The level's record for the event g >= threshold, its CoV from the chains (none at level 0).
SubsetLevel level_record(const LevelSamples& samples, double threshold, long chains, int level,
                         long per_level) {
  std::vector<bool> indicator(samples.g.size());
  for (std::size_t k = 0; k < samples.g.size(); ++k) indicator[k] = samples.g[k] >= threshold;
  SubsetLevel r;
  r.threshold = threshold;
  const auto hits = static_cast<double>(std::count(indicator.begin(), indicator.end(), true));
  r.fraction = hits / static_cast<double>(per_level);
  r.evaluations = samples.evaluations;
  r.acceptance = level == 0 ? std::numeric_limits<double>::quiet_NaN()
                            : static_cast<double>(samples.moves) /
                                  static_cast<double>(std::max(1L, samples.steps));
  r.gamma = level == 0 ? 0.0 : chain_correlation_factor(indicator, chains);
  r.cov =
      std::sqrt((1 - r.fraction) / (static_cast<double>(per_level) * r.fraction) * (1 + r.gamma));
  return r;
}

}  // namespace

double chain_correlation_factor(const std::vector<bool>& indicator, long chains) {
  const auto n = static_cast<long>(indicator.size());
  if (chains < 1 || n % chains != 0)
    throw std::invalid_argument("chain_correlation_factor: chains of unequal length");
  const long length = n / chains;
  const double p = static_cast<double>(std::count(indicator.begin(), indicator.end(), true)) /
                   static_cast<double>(n);
  const double r0 = p * (1 - p);
  if (!(r0 > 0)) return 0.0;
  double gamma = 0;
  for (long lag = 1; lag < length; ++lag) {
    long both = 0;
    for (long c = 0; c < chains; ++c)
      for (long l = 0; l + lag < length; ++l)
        both += indicator[c * length + l] && indicator[c * length + l + lag];
    const double r = static_cast<double>(both) / static_cast<double>(n - lag * chains) - p * p;
    gamma += 2 * (1 - static_cast<double>(lag) / static_cast<double>(length)) * r / r0;
  }
  return gamma;
}

LognormalInterval lognormal_interval(double estimate, double cov, double z) {
  const double s = std::sqrt(std::log1p(cov * cov));
  return {estimate * std::exp(-z * s), estimate * std::exp(z * s)};
}

SubsetResult subset_simulation(int dimension, const BatchLimitState& g, const SubsetSettings& s,
                               const SubsetLevelDone& level_done) {
  require_valid(dimension, s);
  const long seeds_per_level = std::lround(s.p0 * static_cast<double>(s.per_level));
  SubsetResult result;
  LevelSamples samples = independent_level(dimension, g, s);
  double domain = 1, variance = 0;  // P(g >= b_j) of the level's domain; the sum of delta_j^2
  for (int level = 0;; ++level) {
    const std::vector<long> seeds = best_indices(samples.g, seeds_per_level);
    double b = std::numeric_limits<double>::infinity();  // the (p0 N)-th largest g
    for (long k : seeds) b = std::min(b, samples.g[k]);
    const bool last = b >= 0 || level == s.max_levels;
    const SubsetLevel record =
        level_record(samples, last ? 0.0 : b, seeds_per_level, level, s.per_level);
    result.evaluations += record.evaluations;
    result.levels.push_back(record);
    if (level_done) level_done(level, record);
    if (last) {
      result.reached_failure = b >= 0;
      result.estimate = domain * record.fraction;
      break;
    }
    domain *= record.fraction;
    variance += record.cov * record.cov;
    samples = chain_level(samples, seeds, b, level + 1, g, s);
  }
  if (result.estimate > 0) {
    const double last_cov = result.levels.back().cov;
    result.cov = std::sqrt(variance + last_cov * last_cov);
    const LognormalInterval ci = lognormal_interval(result.estimate, result.cov);
    result.lo = ci.lo;
    result.hi = ci.hi;
  } else {  // no failure at the last level allowed: only the domain that holds them is bounded
    result.cov = std::numeric_limits<double>::quiet_NaN();
    result.lo = 0;
    result.hi = domain;
  }
  return result;
}

}  // namespace flexloop::campaign
