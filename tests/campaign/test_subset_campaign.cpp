// SPDX-License-Identifier: BSD-3-Clause
// Subset simulation of a fleet (offline/campaign/subset_campaign.hpp) against an exact
// probability: the one-strut machine under its frozen PI (tests/fixtures/one_strut_campaign.toml)
// with one uncertain number, the piezo actuator's gain, lognormal about 1. Its loop is unstable
// exactly above one critical gain g_c, found here by bisection on flexloop's own verdict (the
// sample status), so P(unstable) = P(gain > g_c) = Phi(-ln(g_c) / sigma_log) exactly. The
// spread is chosen so that P is about 1e-5; subset simulation's estimate must lie within three
// of its stated log-standard deviations of it, by both margins; over 20 seeds its intervals hold
// it in at least 16 and the mean estimate is within 3 standard errors; and the failure margin's
// sign follows the status.
#include <unistd.h>

#include <boost/math/distributions/normal.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/distributions.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/campaign/planned_parameters.hpp"
#include "offline/campaign/subset_campaign.hpp"

using namespace flexloop::campaign;
using nlohmann::json;

namespace {

namespace fs = std::filesystem;

constexpr const char* kGain = "effects.actuator.gain";

struct TempDir {
  fs::path path =
      fs::temp_directory_path() / ("flexloop_test_subset_campaign_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

// A plan of the one-strut machine with a lognormal actuator gain of this relative sd.
json gain_plan(const TempDir& dir, double relative_sd) {
  const fs::path u = dir.path / "gain.toml";
  std::ofstream(u) << "[campaign]\ncontroller = \"frozen\"\n\n[[parameter]]\npath = \"" << kGain
                   << "\"\ndistribution = \"lognormal\"\nrelative_sd = " << relative_sd << "\n";
  PlanRequest r;
  r.scene = "tests/fixtures/one_strut_campaign.toml";
  r.uncertain = u.string();
  r.n = 1;
  r.grid_points = 2;  // sigma_max is not part of the margin: the least grid there is
  return make_plan(r);
}

bool unstable_at(const PlanSamples& samples, double gain) {
  return samples.line_of({{kGain, gain}}, 0)["status"] == "unstable";
}

// The gain where the loop turns unstable, to 1e-12 relative, from a stable and an unstable gain.
double critical_gain(const PlanSamples& samples, double stable, double unstable) {
  REQUIRE_FALSE(unstable_at(samples, stable));
  REQUIRE(unstable_at(samples, unstable));
  while (unstable - stable > 1e-12 * unstable) {
    const double mid = 0.5 * (stable + unstable);
    (unstable_at(samples, mid) ? unstable : stable) = mid;
  }
  return 0.5 * (stable + unstable);
}

// The fleet: the gain's sigma_log = ln(g_c) / 4.265, so that P(gain > g_c) is about 1e-5.
struct OneParameterFleet {
  TempDir dir;
  double g_c = 0, exact = 0;
  json plan;
};

void make_fleet(OneParameterFleet& f) {
  const PlanSamples probe(gain_plan(f.dir, 0.1));
  f.g_c = critical_gain(probe, 1.0, 4.0);
  // Unstable exactly above g_c: the failure domain is the half-line the exact P is the tail of.
  for (double factor : {0.05, 0.3, 0.6, 0.9, 0.999})
    CHECK_FALSE(unstable_at(probe, factor * f.g_c));
  for (double factor : {1.001, 1.1, 1.5, 2.5, 5.0}) CHECK(unstable_at(probe, factor * f.g_c));
  const double sigma_log = std::log(f.g_c) / 4.264890793922825;
  f.plan = gain_plan(f.dir, std::sqrt(std::expm1(sigma_log * sigma_log)));
  const Distribution d = columns_from_plan(f.plan).at(0).distributions.at(0);
  REQUIRE(d.kind == DistributionKind::kLognormal);
  REQUIRE(d.median == 1.0);
  f.exact = cdf(complement(boost::math::normal_distribution<double>(0.0, 1.0),
                           std::log(f.g_c / d.median) / d.sigma_log));
  CHECK(f.exact > 5e-6);
  CHECK(f.exact < 2e-5);
}

SubsetCampaignOptions options(const OneParameterFleet& f, std::uint64_t seed,
                              FailureMargin margin = FailureMargin::kRadius) {
  SubsetCampaignOptions o;
  o.settings.per_level = 500;
  o.settings.seed = seed;
  o.margin = margin;
  o.samples_path = (f.dir.path / "samples.jsonl").string();
  return o;
}

}  // namespace

TEST_CASE("subset simulation of a one-parameter loop finds its exact P(unstable) of 1e-5",
          "[campaign][subset]") {
  OneParameterFleet f;
  make_fleet(f);
  std::vector<double> estimates;
  for (const FailureMargin margin : {FailureMargin::kRadius, FailureMargin::kDisk}) {
    const SubsetCampaignOptions o = options(f, 3, margin);
    const SubsetCampaign c = run_subset_campaign(f.plan, o);
    const SubsetResult& r = c.result;
    const double s = std::sqrt(std::log1p(r.cov * r.cov));
    INFO("margin " << failure_margin_name(margin) << ": g_c = " << f.g_c << ", exact " << f.exact
                   << ", estimate " << r.estimate << " (cov " << r.cov << ") [" << r.lo << ", "
                   << r.hi << "], " << r.evaluations << " evaluations in " << r.levels.size()
                   << " levels");
    CHECK(r.reached_failure);
    CHECK(std::abs(std::log(r.estimate / f.exact)) < 3 * s);
    CHECK(r.levels.size() >= 5);  // one level per decade of 1e-5
    CHECK(r.evaluations < 500 + 450 * 5);
    // Every evaluation is a line with its margin, its sign the status's.
    std::ifstream in(o.samples_path);
    long lines = 0, unstable = 0;
    for (std::string text; std::getline(in, text); ++lines) {
      const json line = json::parse(text);
      const bool failed = line["status"] == "unstable";
      unstable += failed;
      CHECK((failure_margin(line, margin) >= 0) == failed);
    }
    CHECK(lines == r.evaluations);
    CHECK(unstable == c.counts["unstable"].get<long>());
    CHECK(unstable > 0);
    estimates.push_back(r.estimate);
  }
  // In one dimension both margins order the machines as the gain does: the same levels, the
  // same chains' moves, the same estimate.
  CHECK(estimates[0] == estimates[1]);
}

// [long_run]: 18 s at -O2 (run by the check build), over 6 minutes under the sanitizers.
TEST_CASE("subset simulation of a one-parameter loop: over 20 seeds its intervals hold the exact P",
          "[campaign][subset][long_run]") {
  // Seeds 1..20: the lognormal 95 % intervals hold the exact P in most runs and the mean
  // estimate lies within 3 standard errors of it.
  OneParameterFleet f;
  make_fleet(f);
  constexpr int kRuns = 20;
  int covered = 0;
  double sum = 0, sum_squares = 0;
  for (int seed = 1; seed <= kRuns; ++seed) {
    const SubsetResult r =
        run_subset_campaign(f.plan, options(f, static_cast<std::uint64_t>(seed))).result;
    covered += r.lo <= f.exact && f.exact <= r.hi;
    sum += r.estimate;
    sum_squares += r.estimate * r.estimate;
  }
  const double mean = sum / kRuns;
  const double sd = std::sqrt((sum_squares - kRuns * mean * mean) / (kRuns - 1));
  INFO("exact " << f.exact << ", mean " << mean << ", sd " << sd << ", covered " << covered);
  CHECK(std::abs(mean - f.exact) < 3 * sd / std::sqrt(kRuns));
  CHECK(covered >= 16);
}

TEST_CASE("the failure margin: the status's sign, refused and failed machines failing most",
          "[campaign][subset]") {
  const json stable{{"status", "stable"},
                    {"spectral_radius", 1.0000000000000004},
                    {"largest_inner_radius", 0.98},
                    {"disk_margin_db", 6.0}};
  CHECK(failure_margin(stable, FailureMargin::kRadius) == Approx(-0.02));
  CHECK(failure_margin(stable, FailureMargin::kDisk) == -6.0);
  json unbounded = stable;
  unbounded["disk_margin_db"] = "+inf";
  CHECK(failure_margin(unbounded, FailureMargin::kDisk) == -INFINITY);
  json no_disk = stable;
  no_disk["disk_margin_db"] = nullptr;  // a pole on the circle at a grid frequency
  CHECK(failure_margin(no_disk, FailureMargin::kDisk) < 0);
  const json unstable{{"status", "unstable"}, {"spectral_radius", 1.25}};
  CHECK(failure_margin(unstable, FailureMargin::kRadius) == Approx(0.25));
  CHECK(failure_margin(unstable, FailureMargin::kDisk) == Approx(0.25));
  // Unstable only as a continuous loop (its sampled radius below 1): still a failure.
  const json continuous{{"status", "unstable"}, {"spectral_radius", 0.99}};
  CHECK(failure_margin(continuous, FailureMargin::kRadius) == 0);
  for (const char* status : {"refused: buckled", "error: crashed"})
    CHECK(failure_margin(json{{"status", status}, {"spectral_radius", nullptr}},
                         FailureMargin::kRadius) == INFINITY);
}
