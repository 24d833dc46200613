// SPDX-License-Identifier: BSD-3-Clause
// Subset simulation (offline/campaign/subset_simulation.hpp) on analytic limit states in the
// standard normal space, where the probability is known exactly: the linear g = (z_1 + ... +
// z_d) / sqrt(d) - beta has P(g >= 0) = Phi(-beta) in every dimension d. Checked: the estimate
// within its stated CoV of the truth at 1e-5, reproducible by seed; over many seeds the stated
// CoV matches the estimates' spread and the lognormal interval covers the truth about 95 % of the
// time; OpenTURNS's SubsetSampling agrees within the two CoVs; the cost per level.
#include <boost/math/distributions/normal.hpp>
#include <catch2/catch.hpp>
#include <cmath>

#include "offline/campaign/subset_simulation.hpp"
#include "tests/campaign/reference.hpp"

using namespace flexloop::campaign;

namespace {

// (z_1 + ... + z_d) / sqrt(d) - beta, failing (>= 0) with probability Phi(-beta).
BatchLimitState linear_limit_state(double beta, long* evaluations = nullptr) {
  return [beta, evaluations](const NormalPoints& points) {
    std::vector<double> g;
    for (const auto& z : points) {
      double sum = 0;
      for (double x : z) sum += x;
      g.push_back(sum / std::sqrt(static_cast<double>(z.size())) - beta);
    }
    if (evaluations) *evaluations += static_cast<long>(points.size());
    return g;
  };
}

double normal_tail(double beta) {
  return cdf(complement(boost::math::normal_distribution<double>(0.0, 1.0), beta));
}

// |ln(estimate / truth)| in units of the lognormal's s = sqrt(ln(1 + cov^2)).
double log_error_in_sigmas(const SubsetResult& r, double truth) {
  return std::abs(std::log(r.estimate / truth)) / std::sqrt(std::log1p(r.cov * r.cov));
}

}  // namespace

TEST_CASE("subset simulation finds 1e-5 of a linear limit state in 10 dimensions",
          "[campaign][subset]") {
  const double beta = 4.264890793922825;  // Phi(-beta) = 1e-5
  const double truth = normal_tail(beta);
  long counted = 0;
  SubsetSettings s;
  s.per_level = 1000;
  s.seed = 7;
  const SubsetResult r = subset_simulation(10, linear_limit_state(beta, &counted), s);
  INFO("estimate " << r.estimate << ", cov " << r.cov << ", [" << r.lo << ", " << r.hi
                   << "], truth " << truth << ", " << r.levels.size() << " levels");
  CHECK(r.reached_failure);
  CHECK(log_error_in_sigmas(r, truth) < 3);
  CHECK(r.lo < r.estimate);
  CHECK(r.estimate < r.hi);
  CHECK(r.cov > 0.1);  // five levels of 1000: a CoV of a few tenths, not a crude 1/sqrt(N)
  CHECK(r.cov < 0.8);
  // One level per decade: level 0 and four conditional levels, the last one counting failures.
  CHECK(r.levels.size() == 5);
  for (std::size_t j = 0; j + 1 < r.levels.size(); ++j) {
    CHECK(r.levels[j].fraction == Approx(0.1));
    CHECK(r.levels[j].threshold < 0);
    if (j > 0) CHECK(r.levels[j].threshold > r.levels[j - 1].threshold);
  }
  CHECK(r.levels.back().threshold == 0);
  CHECK(r.levels.back().fraction >= 0.1);
  // N at level 0, at most N (1 - p0) at each conditional level (a step where no coordinate moved
  // costs nothing).
  CHECK(r.levels[0].evaluations == 1000);
  for (std::size_t j = 1; j < r.levels.size(); ++j) {
    CHECK(r.levels[j].evaluations <= 900);
    CHECK(r.levels[j].evaluations > 800);
    CHECK(r.levels[j].acceptance > 0.2);
    CHECK(r.levels[j].acceptance < 0.9);
    CHECK(r.levels[j].gamma > 0);
  }
  CHECK(r.evaluations == counted);

  const SubsetResult again = subset_simulation(10, linear_limit_state(beta), s);
  CHECK(again.estimate == r.estimate);
  CHECK(again.cov == r.cov);
  CHECK(again.evaluations == r.evaluations);
  s.seed = 8;
  CHECK(subset_simulation(10, linear_limit_state(beta), s).estimate != r.estimate);
}

TEST_CASE("subset simulation's stated CoV is the spread of its estimates over seeds",
          "[campaign][subset]") {
  // 200 independent runs (seeds 1..200) at P = 1e-5, N = 500: the stated CoV against the
  // estimates' own spread, the bias, and how often the lognormal 95 % interval holds the truth.
  const double beta = 4.264890793922825, truth = normal_tail(beta);
  constexpr int kRuns = 200;
  SubsetSettings s;
  s.per_level = 500;
  double sum = 0, sum_squares = 0, stated_cov = 0;
  int covered = 0;
  for (int run = 1; run <= kRuns; ++run) {
    s.seed = static_cast<std::uint64_t>(run);
    const SubsetResult r = subset_simulation(10, linear_limit_state(beta), s);
    sum += r.estimate;
    sum_squares += r.estimate * r.estimate;
    stated_cov += r.cov / kRuns;
    covered += r.lo <= truth && truth <= r.hi;
  }
  const double mean = sum / kRuns;
  const double sd = std::sqrt((sum_squares - kRuns * mean * mean) / (kRuns - 1));
  const double spread_cov = sd / truth;
  INFO("mean " << mean << " (truth " << truth << "), spread CoV " << spread_cov
               << ", mean stated CoV " << stated_cov << ", covered " << covered << "/" << kRuns);
  // The mean of 200 within 4 standard errors of the truth (the O(1/N) bias is below that).
  CHECK(std::abs(mean - truth) < 4 * sd / std::sqrt(kRuns));
  // The stated CoV (Au & Beck's, between-level correlation left out) within a factor 1.6 of the
  // spread: it understates somewhat, it does not miss by multiples.
  CHECK(stated_cov > spread_cov / 1.6);
  CHECK(stated_cov < spread_cov * 1.6);
  CHECK(covered >= 0.85 * kRuns);
}

TEST_CASE("subset simulation agrees with OpenTURNS's SubsetSampling within their CoVs",
          "[campaign][subset]") {
  // The same event, N = 1000 per level, p0 = 0.1, proposal U(-1, 1) per coordinate in both.
  for (const double beta : {3.090232306167813, 4.264890793922825, 5.199337582192816}) {
    const nlohmann::json ot = test::outside_reference({{"task", "subset_sampling"},
                                                       {"dim", 10},
                                                       {"beta", beta},
                                                       {"n", 1000},
                                                       {"p0", 0.1},
                                                       {"seed", 5}});
    SubsetSettings s;
    s.seed = 5;
    const SubsetResult r = subset_simulation(10, linear_limit_state(beta), s);
    const double ot_estimate = ot["estimate"].get<double>(), ot_cov = ot["cov"].get<double>();
    INFO("beta " << beta << ": flexloop " << r.estimate << " (cov " << r.cov << "), OpenTURNS "
                 << ot_estimate << " (cov " << ot_cov << "), exact " << ot["exact"]);
    CHECK(ot["exact"].get<double>() == Approx(normal_tail(beta)).epsilon(1e-10));
    const double combined = std::sqrt(std::log1p(r.cov * r.cov) + std::log1p(ot_cov * ot_cov));
    CHECK(std::abs(std::log(r.estimate / ot_estimate)) < 3 * combined);
    // The same number of levels but where P sits at a decade's edge (there the last threshold
    // falls either side of 0 by chance: 1e-3 is exactly three levels of p0 = 0.1).
    CHECK(std::abs(static_cast<long>(r.levels.size()) - ot["levels"].get<long>()) <= 1);
  }
}

TEST_CASE(
    "subset simulation of a frequent event is crude Monte Carlo, of an unreachable one a "
    "bound",
    "[campaign][subset]") {
  SubsetSettings s;
  s.per_level = 1000;
  // P = Phi(-1) = 0.16 >= p0: level 0 alone, its share of failures, the binomial CoV.
  const SubsetResult frequent = subset_simulation(3, linear_limit_state(1.0), s);
  REQUIRE(frequent.levels.size() == 1);
  CHECK(frequent.evaluations == 1000);
  CHECK(frequent.cov == Approx(std::sqrt((1 - frequent.estimate) / (1000 * frequent.estimate))));
  CHECK(std::abs(frequent.estimate - normal_tail(1.0)) < 4 * frequent.cov * frequent.estimate);
  // beta = 9 (P = 1e-19) with two conditional levels allowed: no failure, estimate 0, the upper
  // end the last level's domain (about p0^2).
  s.max_levels = 2;
  const SubsetResult capped = subset_simulation(3, linear_limit_state(9.0), s);
  CHECK_FALSE(capped.reached_failure);
  CHECK(capped.levels.size() == 3);
  CHECK(capped.estimate == 0);
  CHECK(std::isnan(capped.cov));
  CHECK(capped.lo == 0);
  CHECK(capped.hi == Approx(0.01));
}

TEST_CASE("the chain correlation factor of independent and of frozen chains",
          "[campaign][subset]") {
  // 10 chains of 10: frozen chains (each all true or all false) have rho(k) = 1 at every lag,
  // gamma = 2 sum_{k=1}^{9} (1 - k/10) = 9; alternating chains R(k) of alternating sign.
  std::vector<bool> frozen(100);
  for (int k = 0; k < 100; ++k) frozen[k] = (k / 10) % 2 == 0;
  CHECK(chain_correlation_factor(frozen, 10) == Approx(9.0));
  CHECK(chain_correlation_factor(std::vector<bool>(100, true), 10) == 0);
  std::vector<bool> alternating(100);
  for (int k = 0; k < 100; ++k) alternating[k] = k % 2 == 0;
  CHECK(chain_correlation_factor(alternating, 10) < 0);
  CHECK_THROWS_AS(chain_correlation_factor(frozen, 7), std::invalid_argument);
}

TEST_CASE("subset simulation refuses settings it cannot honour and a NaN limit state",
          "[campaign][subset]") {
  SubsetSettings s;
  s.per_level = 995;  // p0 N = 99.5 seeds
  CHECK_THROWS_AS(subset_simulation(2, linear_limit_state(3), s), std::invalid_argument);
  s.per_level = 1000;
  s.p0 = 0.3;  // 1/p0 chains' length not whole
  CHECK_THROWS_AS(subset_simulation(2, linear_limit_state(3), s), std::invalid_argument);
  s.p0 = 0.1;
  CHECK_THROWS_AS(subset_simulation(0, linear_limit_state(3), s), std::invalid_argument);
  const BatchLimitState nan = [](const NormalPoints& p) {
    return std::vector<double>(p.size(), std::nan(""));
  };
  CHECK_THROWS_AS(subset_simulation(2, nan, s), std::invalid_argument);
  const BatchLimitState short_answer = [](const NormalPoints&) { return std::vector<double>{}; };
  CHECK_THROWS_AS(subset_simulation(2, short_answer, s), std::invalid_argument);
}

TEST_CASE("subset simulation's cost per decade on the linear limit state (prints a table)",
          "[.subset_cost]") {
  // doc/performance.md "Rare failures": evaluations, levels and time for P = 1e-3, 1e-5, 1e-7
  // in 10 dimensions, N = 1000, seeds 1..20 (the evaluations vary with the seed a little).
  for (const double beta : {3.090232306167813, 4.264890793922825, 5.199337582192816}) {
    SubsetSettings s;
    long evaluations = 0, levels = 0;
    double log_error = 0, cov = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int seed = 1; seed <= 20; ++seed) {
      s.seed = static_cast<std::uint64_t>(seed);
      const SubsetResult r = subset_simulation(10, linear_limit_state(beta), s);
      evaluations += r.evaluations;
      levels += static_cast<long>(r.levels.size());
      log_error += std::pow(std::log(r.estimate / normal_tail(beta)), 2) / 20;
      cov += r.cov / 20;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 20;
    WARN("P = " << normal_tail(beta) << ": mean evaluations " << evaluations / 20.0
                << ", mean levels " << levels / 20.0 << ", mean stated CoV " << cov
                << ", rms log error " << std::sqrt(log_error) << ", " << seconds * 1e3
                << " ms a run");
  }
}
