// SPDX-License-Identifier: BSD-3-Clause
// The distributions' inverse CDFs (offline/campaign/distributions.hpp) against scipy.stats
// (python3-scipy): uniform, normal, lognormal (median and relative sd), truncated normal (below,
// in the upper tail, two-sided); the cut tails at kTailProbability.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "offline/campaign/distributions.hpp"

namespace {

// Using-declarations, not directives: the area's test files share unity batches.
using flexloop::campaign::Distribution;
using flexloop::campaign::distribution_from_json;
using flexloop::campaign::DistributionKind;
using flexloop::campaign::highest_draw;
using flexloop::campaign::inverse_cdf;
using flexloop::campaign::kTailProbability;
using flexloop::campaign::lognormal_sigma_from_relative_sd;
using flexloop::campaign::lowest_draw;
using flexloop::campaign::to_json;

const std::vector<double> kUnits = {0.0, 1e-6, 0.001, 0.1, 0.37, 0.5, 0.9, 0.999, 1 - 1e-7};

// scipy's ppf of `frozen` (a scipy.stats expression) at each u, u clamped like ours for the
// unbounded distributions when `cut` is true.
std::vector<double> scipy_ppf(const std::string& frozen, bool cut) {
  std::ostringstream script;
  script.precision(17);
  script << "from scipy import stats\nimport numpy as np\nd = stats." << frozen << "\nfor u in [";
  for (double u : kUnits) script << u << ",";
  script << "]:\n    u = min(max(u, 1e-9), 1 - 1e-9) if " << (cut ? "True" : "False")
         << " else u\n    print(repr(float(d.ppf(u))))\n";
  // Debian's python3 (scipy is a Debian package; a python3 earlier on PATH may lack it).
  const std::string command = "/usr/bin/python3 -c '" + script.str() + "'";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  REQUIRE(pipe);
  std::vector<double> out;
  char line[128];
  while (std::fgets(line, sizeof line, pipe.get())) out.push_back(std::stod(line));
  REQUIRE(out.size() == kUnits.size());
  return out;
}

void require_matches(const Distribution& d, const std::string& frozen, bool cut, double rel) {
  const std::vector<double> reference = scipy_ppf(frozen, cut);
  for (std::size_t i = 0; i < kUnits.size(); ++i) {
    INFO(frozen << " at u = " << kUnits[i]);
    CHECK(inverse_cdf(d, kUnits[i]) == Approx(reference[i]).epsilon(rel).margin(1e-300));
  }
}

}  // namespace

TEST_CASE("uniform and normal inverse CDFs equal scipy's ppf", "[campaign][distributions]") {
  Distribution u;
  u.low = 600, u.high = 1000;
  require_matches(u, "uniform(loc=600, scale=400)", false, 1e-14);
  Distribution n;
  n.kind = DistributionKind::kNormal, n.mean = 5.26e6, n.sd = 0.05 * 5.26e6;
  require_matches(n, "norm(loc=5.26e6, scale=0.05 * 5.26e6)", true, 1e-12);
}

TEST_CASE("the lognormal's median and relative sd are those of scipy's lognorm",
          "[campaign][distributions]") {
  Distribution d;
  d.kind = DistributionKind::kLognormal, d.median = 167.55;
  d.sigma_log = lognormal_sigma_from_relative_sd(0.3);
  require_matches(d, "lognorm(s=np.sqrt(np.log1p(0.3**2)), scale=167.55)", true, 1e-12);
  // sd(X) / mean(X) of that lognormal is the relative sd asked for: exp(s^2) - 1 = r^2.
  CHECK(std::sqrt(std::expm1(d.sigma_log * d.sigma_log)) == Approx(0.3).epsilon(1e-14));
  CHECK(inverse_cdf(d, 0.5) == Approx(167.55).epsilon(1e-14));
}

TEST_CASE("truncated normal inverse CDFs equal scipy's truncnorm, in either tail",
          "[campaign][distributions]") {
  Distribution below;  // truncated below only (a stiffness kept positive)
  below.kind = DistributionKind::kTruncatedNormal, below.mean = 1.0, below.sd = 0.5,
  below.low = 0.2;
  require_matches(below, "truncnorm(a=(0.2 - 1.0) / 0.5, b=np.inf, loc=1.0, scale=0.5)", false,
                  1e-10);
  Distribution tail;  // both bounds far in the upper tail: the complement's precision
  tail.kind = DistributionKind::kTruncatedNormal, tail.mean = 0, tail.sd = 1, tail.low = 3,
  tail.high = 5;
  require_matches(tail, "truncnorm(a=3, b=5)", false, 1e-9);
  Distribution both;
  both.kind = DistributionKind::kTruncatedNormal, both.mean = 1, both.sd = 0.1, both.low = 0.7,
  both.high = 1.3;
  require_matches(both, "truncnorm(a=-3, b=3, loc=1, scale=0.1)", false, 1e-12);
  for (double u : kUnits) {
    CHECK(inverse_cdf(both, u) >= 0.7);
    CHECK(inverse_cdf(both, u) <= 1.3);
  }
  // Bounded above only (issue 54): u = 0 is cut at the 1e-9 quantile as the normal's, not -inf;
  // u = 1 is the bound.
  Distribution above;
  above.kind = DistributionKind::kTruncatedNormal, above.mean = 1, above.sd = 0.1, above.high = 1.1;
  require_matches(above, "truncnorm(a=-np.inf, b=1, loc=1, scale=0.1)", true, 1e-10);
  CHECK(std::isfinite(inverse_cdf(above, 0.0)));
  CHECK(inverse_cdf(above, 1.0) == Approx(1.1).epsilon(1e-12));
}

TEST_CASE("the unbounded tails are cut at the 1e-9 quantiles, the bounds the planning judges",
          "[campaign][distributions]") {
  Distribution n;
  n.kind = DistributionKind::kNormal, n.mean = 0, n.sd = 1;
  CHECK(std::isfinite(inverse_cdf(n, 0.0)));
  CHECK(lowest_draw(n) == inverse_cdf(n, kTailProbability));
  CHECK(lowest_draw(n) == Approx(-5.997807015).epsilon(1e-9));  // Phi^-1(1e-9), by Wichura's AS241
  // Symmetric up to the rounding of 1 - 1e-9 in double (1.1e-16 of 1e-9: 1e-7 relative in u).
  CHECK(highest_draw(n) == Approx(-lowest_draw(n)).epsilon(1e-8));
  // The plan's record of a distribution reads back as the same distribution.
  Distribution t;
  t.kind = DistributionKind::kTruncatedNormal, t.mean = 2, t.sd = 0.3, t.low = 1;
  const Distribution back = distribution_from_json(to_json(t));
  CHECK(back.low == 1);
  CHECK(std::isinf(back.high));
  CHECK(inverse_cdf(back, 0.42) == inverse_cdf(t, 0.42));
}
