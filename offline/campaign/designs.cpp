// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/designs.hpp"

#include <algorithm>
#include <boost/random/sobol.hpp>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "common/input_error.hpp"
#include "offline/campaign/counter_random.hpp"

namespace flexloop::campaign {

struct DesignPoints::SobolEngine {
  boost::random::sobol engine;
};

namespace {

constexpr std::uint64_t kStrataTag = 0x4C48532D7065726Dull;  // "LHS-perm": apart from jitters
constexpr int kSobolMaxDimension = 3667;                     // Boost's Joe-Kuo table

// pi(0..n-1): Fisher-Yates (Durstenfeld) from the end, swap partner uniform on {0..i}.
std::vector<std::uint32_t> strata_permutation(long n, std::uint64_t seed, int dimension) {
  std::vector<std::uint32_t> pi(static_cast<std::size_t>(n));
  for (long i = 0; i < n; ++i) pi[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(i);
  CounterStream stream(splitmix64(seed ^ kStrataTag), static_cast<std::uint64_t>(dimension));
  for (long i = n - 1; i > 0; --i) {
    const auto j = static_cast<long>(stream.below(static_cast<std::uint64_t>(i) + 1));
    std::swap(pi[static_cast<std::size_t>(i)], pi[static_cast<std::size_t>(j)]);
  }
  return pi;
}

// (stratum + u) / n, kept inside the stratum where rounding would carry it to the next one.
double in_stratum(std::uint32_t stratum, double u, long n) {
  const double upper = (stratum + 1.0) / static_cast<double>(n);
  double x = (stratum + u) / static_cast<double>(n);
  while (x >= upper) x = std::nextafter(x, 0.0);
  return x;
}

}  // namespace

DesignKind design_kind_from_name(const std::string& name) {
  if (name == "random") return DesignKind::kRandom;
  if (name == "lhs") return DesignKind::kLatinHypercube;
  if (name == "sobol") return DesignKind::kSobol;
  if (name == "saltelli") return DesignKind::kSaltelli;
  throw common::InputError(
      "", "unknown design '" + name + "' (valid designs: random, lhs, sobol, saltelli)");
}

std::string design_name(DesignKind kind) {
  switch (kind) {
    case DesignKind::kRandom:
      return "random";
    case DesignKind::kLatinHypercube:
      return "lhs";
    case DesignKind::kSobol:
      return "sobol";
    case DesignKind::kSaltelli:
      return "saltelli";
  }
  throw std::invalid_argument("design_name: not a DesignKind");
}

long evaluation_count(DesignKind kind, long n, int d) {
  return kind == DesignKind::kSaltelli ? n * (d + 2L) : n;
}

DesignPoints::DesignPoints(DesignKind kind, long n, int d, std::uint64_t seed)
    : kind_(kind), n_(n), d_(d), seed_(seed) {
  if (n < 1) throw std::invalid_argument("design: n = " + std::to_string(n) + ", need n >= 1");
  if (d < 1) throw std::invalid_argument("design: d = " + std::to_string(d) + ", need d >= 1");
  const int sobol_dims = kind == DesignKind::kSaltelli ? 2 * d : d;
  if ((kind == DesignKind::kSobol || kind == DesignKind::kSaltelli) &&
      sobol_dims > kSobolMaxDimension)
    throw std::invalid_argument("design " + design_name(kind) + ": " + std::to_string(d) +
                                " parameters need a " + std::to_string(sobol_dims) +
                                "-dimensional Sobol sequence; the table has " +
                                std::to_string(kSobolMaxDimension));
  if (kind == DesignKind::kLatinHypercube) {
    if (n > 0xFFFFFFFFL) throw std::invalid_argument("design lhs: n beyond 2^32 - 1");
    for (int k = 0; k < d; ++k) strata_.push_back(strata_permutation(n, seed, k));
  }
  if (kind == DesignKind::kSobol || kind == DesignKind::kSaltelli)
    sobol_ = std::make_shared<const SobolEngine>(
        SobolEngine{boost::random::sobol(static_cast<std::size_t>(sobol_dims))});
}

// Point `point` (>= 1) of the design's Sobol sequence; Boost's engine starts at point 1, so
// seed(point - 1) puts a copy of it there (Gray-code jump, O(dimension * bits)).
std::vector<double> DesignPoints::sobol_point(long point) const {
  boost::random::sobol engine = sobol_->engine;
  engine.seed(static_cast<std::uint64_t>(point - 1));
  std::vector<double> x(engine.dimension());
  for (double& v : x) v = unit_from_bits(engine());
  return x;
}

std::vector<double> DesignPoints::point(long index) const {
  if (index < 0 || index >= size())
    throw std::out_of_range("design " + design_name(kind_) + ": evaluation " +
                            std::to_string(index) + " outside 0.." + std::to_string(size() - 1));
  const auto d = static_cast<std::size_t>(d_);
  std::vector<double> x(d);
  const auto i = static_cast<std::uint64_t>(index);
  switch (kind_) {
    case DesignKind::kRandom:
      for (std::size_t k = 0; k < d; ++k) x[k] = unit_from_bits(counter_bits(seed_, i, k));
      return x;
    case DesignKind::kLatinHypercube:
      for (std::size_t k = 0; k < d; ++k)
        x[k] = in_stratum(strata_[k][i], unit_from_bits(counter_bits(seed_, i, k)), n_);
      return x;
    case DesignKind::kSobol:
      return sobol_point(index + 1);
    case DesignKind::kSaltelli: {
      const long block = index / (d_ + 2L);
      const long j = index % (d_ + 2L);
      const std::vector<double> ab = sobol_point(block + 1);  // [A_b | B_b]
      const std::size_t offset = j == 1 ? d : 0;              // j == 1: all of B_b, else A_b
      for (std::size_t k = 0; k < d; ++k) x[k] = ab[offset + k];
      if (j >= 2) x[static_cast<std::size_t>(j - 2)] = ab[d + static_cast<std::size_t>(j - 2)];
      return x;
    }
  }
  throw std::invalid_argument("design: not a DesignKind");
}

std::vector<double> unit_point(DesignKind kind, long n, int d, std::uint64_t seed, long index) {
  thread_local std::unique_ptr<DesignPoints> last;
  if (!last || last->kind() != kind || last->n() != n || last->d() != d || last->seed() != seed)
    last = std::make_unique<DesignPoints>(kind, n, d, seed);
  return last->point(index);
}

}  // namespace flexloop::campaign
