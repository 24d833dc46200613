// SPDX-License-Identifier: BSD-3-Clause
// The campaign's estimators (offline/campaign/statistics.hpp) against outside references:
// order-statistic ranks against SciPy's binomial (brute force) and OpenTURNS's Wilks sample
// sizes, Clopper-Pearson against SciPy's beta quantiles, coverage by simulation, and the Sobol
// indices of the Ishigami function against OpenTURNS and the analytic values.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "offline/campaign/counter_random.hpp"
#include "offline/campaign/designs.hpp"
#include "offline/campaign/statistics.hpp"
#include "tests/campaign/reference.hpp"

using namespace flexloop::campaign;

TEST_CASE("quantile interval ranks equal a brute-force search over SciPy's binomial",
          "[campaign][statistics]") {
  nlohmann::json cases = nlohmann::json::array();
  for (long n : {1L, 2L, 5L, 10L, 20L, 44L, 58L, 59L, 100L, 137L, 300L})
    for (double p : {0.05, 0.5, 0.95})
      for (double confidence : {0.9, 0.95}) cases.push_back({n, p, confidence});
  const nlohmann::json scipy =
      test::outside_reference({{"task", "quantile_ranks"}, {"cases", cases}});
  REQUIRE(scipy.size() == cases.size());
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const long n = cases[c][0];
    const double p = cases[c][1], confidence = cases[c][2];
    INFO("n = " << n << ", p = " << p << ", confidence " << confidence);
    const RankInterval r = quantile_ranks(n, p, confidence);
    CHECK(r.lo_rank == scipy[c]["lo_rank"].get<long>());
    CHECK(r.hi_rank == scipy[c]["hi_rank"].get<long>());
    CHECK(r.coverage == Approx(scipy[c]["coverage"].get<double>()).epsilon(1e-10));
    CHECK(r.coverage >= confidence);
  }
}

TEST_CASE("the upper end becomes the sample maximum at OpenTURNS's Wilks sample size",
          "[campaign][statistics]") {
  // Wilks: the max of n samples bounds the p-quantile with confidence beta from n on (59 for
  // p = beta = 0.95); one sample fewer, no finite interval reaches beta: the upper end is +inf.
  const std::vector<std::pair<double, double>> levels{{0.95, 0.95}, {0.99, 0.95}, {0.9, 0.99}};
  nlohmann::json cases = nlohmann::json::array();
  for (const auto& [p, beta] : levels) cases.push_back({p, beta, 0});
  const nlohmann::json wilks = test::outside_reference({{"task", "wilks"}, {"cases", cases}});
  CHECK(wilks[0].get<long>() == 59);
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const auto [p, beta] = levels[k];
    const long n = wilks[k].get<long>();
    INFO("p = " << p << ", confidence " << beta << ", Wilks n = " << n);
    std::vector<double> xs;
    for (long i = 0; i < n; ++i) xs.push_back(static_cast<double>((i * 37) % n));
    const QuantileInterval at_n = quantile_interval(xs, p, beta);
    CHECK(at_n.hi_rank == n);
    CHECK(at_n.hi == static_cast<double>(n - 1));  // the maximum
    CHECK(at_n.confidence >= beta);
    xs.pop_back();
    const QuantileInterval below_n = quantile_interval(xs, p, beta);
    CHECK(below_n.hi_rank == n);  // = (n - 1) + 1: the infinite end
    CHECK(std::isinf(below_n.hi));
  }
}

TEST_CASE("a quantile interval covers the true quantile at its stated rate",
          "[campaign][statistics]") {
  // Exponential(1) samples of 25, drawn with the campaign's own generator: quantile -ln(1 - p).
  const int trials = 4000;
  const long n = 25;
  for (double p : {0.05, 0.5, 0.95}) {
    const double truth = -std::log1p(-p);
    long covered = 0;
    double stated = 0.0;
    for (int t = 0; t < trials; ++t) {
      CounterStream stream(77, static_cast<std::uint64_t>(t));
      std::vector<double> xs;
      for (long i = 0; i < n; ++i) xs.push_back(-std::log1p(-stream.unit()));
      const QuantileInterval q = quantile_interval(xs, p, 0.95);
      covered += q.lo <= truth && truth <= q.hi;
      stated = q.confidence;
    }
    INFO("p = " << p << ": covered " << covered << " of " << trials << ", stated " << stated);
    CHECK(stated >= 0.95);
    const double sd = std::sqrt(trials * stated * (1.0 - stated));
    CHECK(std::abs(static_cast<double>(covered) - trials * stated) <= 4.0 * sd + 1.0);
  }
}

TEST_CASE("Clopper-Pearson equals SciPy's beta quantiles, with the k = 0 and k = n ends",
          "[campaign][statistics]") {
  nlohmann::json cases = nlohmann::json::array();
  for (const auto& [k, n] : std::vector<std::pair<long, long>>{{0, 1},
                                                               {1, 1},
                                                               {0, 10},
                                                               {10, 10},
                                                               {1, 10},
                                                               {3, 50},
                                                               {17, 1000},
                                                               {500, 1000},
                                                               {0, 10000}})
    for (double confidence : {0.9, 0.95, 0.99}) cases.push_back({k, n, confidence});
  const nlohmann::json scipy =
      test::outside_reference({{"task", "clopper_pearson"}, {"cases", cases}});
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const long k = cases[c][0], n = cases[c][1];
    const double confidence = cases[c][2];
    INFO(k << " of " << n << ", confidence " << confidence);
    const Interval ci = clopper_pearson(k, n, confidence);
    CHECK(ci.estimate == static_cast<double>(k) / static_cast<double>(n));
    CHECK(ci.lo == Approx(scipy[c]["lo"].get<double>()).epsilon(1e-11).margin(1e-300));
    CHECK(ci.hi == Approx(scipy[c]["hi"].get<double>()).epsilon(1e-11));
  }
  // k = 0: the upper end is 1 - (alpha/2)^(1/n) (the rule of three's exact form).
  CHECK(clopper_pearson(0, 100).hi == Approx(1.0 - std::pow(0.025, 0.01)).epsilon(1e-12));
  CHECK(std::isnan(clopper_pearson(0, 0).estimate));
}

TEST_CASE("a Clopper-Pearson interval holds the true proportion at least at its confidence",
          "[campaign][statistics]") {
  const int trials = 3000;
  const long n = 60;
  const double truth = 0.1;
  long covered = 0;
  for (int t = 0; t < trials; ++t) {
    CounterStream stream(5, static_cast<std::uint64_t>(t));
    long k = 0;
    for (long i = 0; i < n; ++i) k += stream.unit() < truth;
    const Interval ci = clopper_pearson(k, n);
    covered += ci.lo <= truth && truth <= ci.hi;
  }
  // Conservative by construction: coverage >= 95 %, less 4 standard deviations of the count.
  CHECK(covered >= trials * 0.95 - 4.0 * std::sqrt(trials * 0.95 * 0.05));
}

namespace {

// Ishigami: sin x1 + a sin^2 x2 + b x3^4 sin x1 on [-pi, pi]^3 (a = 7, b = 0.1).
constexpr double kA = 7.0, kB = 0.1;
double ishigami(const std::vector<double>& u) {
  const double pi = std::numbers::pi;
  const double x1 = -pi + 2 * pi * u[0], x2 = -pi + 2 * pi * u[1], x3 = -pi + 2 * pi * u[2];
  return std::sin(x1) + kA * std::sin(x2) * std::sin(x2) + kB * std::pow(x3, 4) * std::sin(x1);
}

}  // namespace

TEST_CASE(
    "Sobol indices of the Ishigami function: OpenTURNS's on the same samples, the "
    "analytic ones inside the bootstrap intervals",
    "[campaign][statistics]") {
  const long n = 4096;
  const int d = 3;
  std::vector<double> y;
  nlohmann::json x = nlohmann::json::array();
  for (long i = 0; i < evaluation_count(DesignKind::kSaltelli, n, d); ++i) {
    const std::vector<double> u = unit_point(DesignKind::kSaltelli, n, d, 1, i);
    y.push_back(ishigami(u));
    for (double v : u) x.push_back(v);
  }
  const std::vector<SobolIndex> s = sobol_indices(y, n, d, 500, 3);
  const nlohmann::json ot =
      test::outside_reference({{"task", "sobol_indices"}, {"n", n}, {"d", d}, {"x", x}, {"y", y}});
  // Analytic (Ishigami and Homma 1990): V_1 = (1 + b pi^4/5)^2 / 2, V_2 = a^2/8, V_3 = 0,
  // V_13 = 8 b^2 pi^8 / 225, V = V_1 + V_2 + V_13.
  const double pi4 = std::pow(std::numbers::pi, 4), pi8 = pi4 * pi4;
  const double v1 = 0.5 * std::pow(1 + kB * pi4 / 5, 2), v2 = kA * kA / 8,
               v13 = 8 * kB * kB * pi8 / 225;
  const double v = v1 + v2 + v13;
  const double first[] = {v1 / v, v2 / v, 0.0}, total[] = {(v1 + v13) / v, v2 / v, v13 / v};
  CHECK(first[0] == Approx(0.3139).margin(1e-4));
  CHECK(total[2] == Approx(0.2437).margin(1e-4));
  for (std::size_t i = 0; i < 3; ++i) {
    INFO("parameter " << i + 1 << ": first " << s[i].first.estimate << " [" << s[i].first.lo << ", "
                      << s[i].first.hi << "], total " << s[i].total.estimate << " ["
                      << s[i].total.lo << ", " << s[i].total.hi << "]");
    CHECK(s[i].first.estimate == Approx(ot["first"][i].get<double>()).margin(1e-12));
    CHECK(s[i].total.estimate == Approx(ot["total"][i].get<double>()).margin(1e-12));
    CHECK((s[i].first.lo <= first[i] && first[i] <= s[i].first.hi));
    CHECK((s[i].total.lo <= total[i] && total[i] <= s[i].total.hi));
    CHECK(s[i].first.hi - s[i].first.lo < 0.1);
    CHECK(s[i].total_holds_zero == false);
  }
  CHECK(s[0].first_holds_zero == false);
  CHECK(s[1].first_holds_zero == false);
  CHECK(s[2].first_holds_zero == true);  // x3 acts only through its interaction with x1
  // The same seed gives the same intervals; another seed other ones.
  CHECK(sobol_indices(y, n, d, 500, 3)[0].first.lo == s[0].first.lo);
  CHECK(sobol_indices(y, n, d, 500, 4)[0].first.lo != s[0].first.lo);
}

TEST_CASE("estimators refuse what they cannot use", "[campaign][statistics]") {
  CHECK_THROWS_AS(quantile_interval({1.0, NAN}, 0.5), std::invalid_argument);
  CHECK_THROWS_AS(quantile_interval({1.0}, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(clopper_pearson(3, 2), std::invalid_argument);
  CHECK_THROWS_AS(sobol_indices(std::vector<double>(9, 1.0), 2, 3), std::invalid_argument);
  const QuantileInterval empty = quantile_interval({}, 0.5);
  CHECK(std::isnan(empty.estimate));
  CHECK((std::isinf(empty.lo) && empty.lo < 0 && std::isinf(empty.hi)));
  // Constant outputs: no variance to share out.
  const std::vector<SobolIndex> flat = sobol_indices(std::vector<double>(10, 2.0), 2, 3);
  CHECK(std::isnan(flat[0].first.estimate));
}
