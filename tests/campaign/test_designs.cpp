// SPDX-License-Identifier: BSD-3-Clause
// The unit designs (offline/campaign/designs.hpp): purity, the Latin hypercube's strata, the
// Sobol sequence against SciPy's, the Saltelli layout, and uniformity measured by OpenTURNS.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "common/input_error.hpp"
#include "offline/campaign/designs.hpp"
#include "tests/campaign/reference.hpp"

using namespace flexloop::campaign;

TEST_CASE("design names round-trip, an unknown one is an input error naming the valid ones",
          "[campaign][designs]") {
  for (const char* name : {"random", "lhs", "sobol", "saltelli"})
    CHECK(design_name(design_kind_from_name(name)) == name);
  try {
    design_kind_from_name("halton");
    FAIL("no error for an unknown design");
  } catch (const flexloop::common::InputError& e) {
    CHECK(std::string(e.what()).find("halton") != std::string::npos);
    CHECK(std::string(e.what()).find("saltelli") != std::string::npos);
  }
  CHECK(evaluation_count(DesignKind::kRandom, 100, 7) == 100);
  CHECK(evaluation_count(DesignKind::kSaltelli, 100, 7) == 900);
  CHECK_THROWS_AS(DesignPoints(DesignKind::kRandom, 0, 3, 1), std::invalid_argument);
  CHECK_THROWS_AS(unit_point(DesignKind::kLatinHypercube, 10, 2, 1, 10), std::out_of_range);
}

TEST_CASE("a point depends only on (kind, n, d, seed, index), in any order of asking",
          "[campaign][designs]") {
  for (DesignKind kind : {DesignKind::kRandom, DesignKind::kLatinHypercube, DesignKind::kSobol,
                          DesignKind::kSaltelli}) {
    const long n = 37;
    const int d = 3;
    const DesignPoints design(kind, n, d, 42);
    const long count = evaluation_count(kind, n, d);
    // Backwards through unit_point, interleaved with another design (the per-thread cache).
    for (long i = count - 1; i >= 0; --i) {
      const std::vector<double> x = unit_point(kind, n, d, 42, i);
      (void)unit_point(DesignKind::kRandom, 5, 1, 7, 0);
      REQUIRE(x == design.point(i));
      for (double v : x) REQUIRE((v >= 0.0 && v < 1.0));
    }
  }
  // The seed matters where a design has randomness; a random point does not depend on n.
  CHECK(unit_point(DesignKind::kRandom, 10, 2, 1, 3) !=
        unit_point(DesignKind::kRandom, 10, 2, 2, 3));
  CHECK(unit_point(DesignKind::kRandom, 10, 2, 1, 3) ==
        unit_point(DesignKind::kRandom, 99, 2, 1, 3));
  CHECK(unit_point(DesignKind::kLatinHypercube, 10, 2, 1, 3) !=
        unit_point(DesignKind::kLatinHypercube, 10, 2, 2, 3));
}

TEST_CASE("a Latin hypercube hits each of the n strata once per dimension", "[campaign][designs]") {
  for (long n : {1L, 2L, 7L, 1000L}) {
    const int d = 5;
    const DesignPoints design(DesignKind::kLatinHypercube, n, d, 2024);
    std::vector<std::set<long>> hit(d);
    for (long i = 0; i < n; ++i) {
      const std::vector<double> x = design.point(i);
      for (int k = 0; k < d; ++k)
        hit[static_cast<std::size_t>(k)].insert(
            static_cast<long>(std::floor(x[static_cast<std::size_t>(k)] * static_cast<double>(n))));
    }
    for (const auto& strata : hit) {
      CHECK(static_cast<long>(strata.size()) == n);
      CHECK(*strata.begin() == 0);
      CHECK(*strata.rbegin() == n - 1);
    }
  }
}

TEST_CASE("the Sobol design is SciPy's unscrambled Sobol sequence without its origin",
          "[campaign][designs]") {
  const int d = 5;
  const long count = 300;
  const nlohmann::json scipy =
      test::outside_reference({{"task", "sobol_points"}, {"dim", d}, {"count", count + 1}});
  for (long i = 0; i < count; ++i)
    REQUIRE(unit_point(DesignKind::kSobol, count, d, 1, i) ==
            scipy[static_cast<std::size_t>(i + 1)].get<std::vector<double>>());
}

TEST_CASE(
    "Saltelli blocks: A and B from the 2d-dimensional Sobol sequence, then A with one "
    "column of B",
    "[campaign][designs]") {
  const int d = 3;
  const long n = 64;
  const nlohmann::json scipy =
      test::outside_reference({{"task", "sobol_points"}, {"dim", 2 * d}, {"count", n + 1}});
  for (long b = 0; b < n; ++b) {
    const auto ab = scipy[static_cast<std::size_t>(b + 1)].get<std::vector<double>>();
    const std::vector<double> a(ab.begin(), ab.begin() + d), bb(ab.begin() + d, ab.end());
    REQUIRE(unit_point(DesignKind::kSaltelli, n, d, 1, b * (d + 2)) == a);
    REQUIRE(unit_point(DesignKind::kSaltelli, n, d, 1, b * (d + 2) + 1) == bb);
    for (int i = 0; i < d; ++i) {
      std::vector<double> e = a;
      e[static_cast<std::size_t>(i)] = bb[static_cast<std::size_t>(i)];
      REQUIRE(unit_point(DesignKind::kSaltelli, n, d, 1, b * (d + 2) + 2 + i) == e);
    }
  }
}

TEST_CASE("uniformity by OpenTURNS's centred L2 discrepancy: Sobol < Latin hypercube < random",
          "[campaign][designs]") {
  const long n = 512;
  const int d = 4;
  nlohmann::json samples;
  for (DesignKind kind : {DesignKind::kRandom, DesignKind::kLatinHypercube, DesignKind::kSobol}) {
    nlohmann::json pts = nlohmann::json::array();
    for (long i = 0; i < n; ++i) pts.push_back(unit_point(kind, n, d, 11, i));
    samples[design_name(kind)] = pts;
  }
  const nlohmann::json c2 =
      test::outside_reference({{"task", "c2_discrepancy"}, {"samples", samples}});
  INFO("C2: " << c2.dump());
  CHECK(c2["sobol"].get<double>() < 0.5 * c2["lhs"].get<double>());
  CHECK(c2["lhs"].get<double>() < c2["random"].get<double>());
}

TEST_CASE("each coordinate of the random design passes Kolmogorov-Smirnov against U(0,1)",
          "[campaign][designs]") {
  const long n = 2000;
  const int d = 6;
  for (int k = 0; k < d; ++k) {
    std::vector<double> x;
    for (long i = 0; i < n; ++i)
      x.push_back(unit_point(DesignKind::kRandom, n, d, 5, i)[static_cast<std::size_t>(k)]);
    std::sort(x.begin(), x.end());
    double ks = 0.0;
    for (long i = 0; i < n; ++i) {
      const double xi = x[static_cast<std::size_t>(i)];
      ks = std::max({ks, (i + 1.0) / static_cast<double>(n) - xi,
                     xi - static_cast<double>(i) / static_cast<double>(n)});
    }
    // Kolmogorov's 0.1 % critical value 1.95 / sqrt(n): six dimensions, a false alarm at 0.6 %.
    CHECK(ks < 1.95 / std::sqrt(static_cast<double>(n)));
  }
}
