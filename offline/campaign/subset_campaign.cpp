// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/subset_campaign.hpp"

#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/campaign/planned_parameters.hpp"
#include "offline/campaign/sample_table.hpp"

namespace flexloop::campaign {

using nlohmann::json;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The largest g a machine judged stable may have: failure is g >= 0, so never 0 itself.
constexpr double kJustSafe = -std::numeric_limits<double>::denorm_min();

// The stable side's margin, below 0.
double stable_margin(const json& sample, FailureMargin margin) {
  if (margin == FailureMargin::kRadius) {
    const double r = figure_value(sample.value("largest_inner_radius", json()));
    return std::isnan(r) ? kJustSafe : std::min(r - 1, kJustSafe);
  }
  const double db = figure_value(sample.value("disk_margin_db", json()));
  return std::isnan(db) ? kJustSafe : std::min(-db, kJustSafe);
}

// u = Phi(z), from the tail on each side (no 1 - small rounding for z < 0).
double normal_cdf(double z) {
  const boost::math::normal_distribution<double> standard(0.0, 1.0);
  return z < 0 ? cdf(standard, z) : 1 - cdf(complement(standard, z));
}

void require_subset_plan(const json& plan) {
  if (plan_simulate_s(plan) > 0)
    throw common::InputError("--method subset",
                             "a subset campaign judges the loop's poles: --simulate is not "
                             "part of it");
}

}  // namespace

FailureMargin failure_margin_from_name(const std::string& name) {
  if (name == "radius") return FailureMargin::kRadius;
  if (name == "disk") return FailureMargin::kDisk;
  throw common::InputError("--margin", "'" + name + "' is not radius or disk");
}

std::string failure_margin_name(FailureMargin margin) {
  return margin == FailureMargin::kRadius ? "radius" : "disk";
}

double failure_margin(const json& sample, FailureMargin margin) {
  switch (sample_status(sample)) {
    case SampleStatus::kUnstable: {
      const double r = figure_value(sample.value("spectral_radius", json()));
      return std::isnan(r) ? 0.0 : std::max(r - 1, 0.0);
    }
    case SampleStatus::kRefused:
    case SampleStatus::kError:
      return kInfinity;
    case SampleStatus::kStable:
    case SampleStatus::kMarginal:
      break;
  }
  return stable_margin(sample, margin);
}

SubsetCampaign run_subset_campaign(const json& plan, const SubsetCampaignOptions& o) {
  require_subset_plan(plan);
  const PlanSamples samples(plan);
  const std::vector<PlannedColumn> columns = columns_from_plan(plan);
  std::FILE* out = std::fopen(o.samples_path.c_str(), "wb");
  if (!out) throw common::InputError(o.samples_path, "cannot be written");
  SubsetCampaign c;
  long index = 0, counts[std::size(kStatusNames)] = {};
  const BatchLimitState g = [&](const NormalPoints& points) {
    std::vector<double> margins;
    for (const auto& z : points) {
      std::vector<double> u(z.size());
      for (std::size_t i = 0; i < z.size(); ++i) u[i] = normal_cdf(z[i]);
      json line = samples.line_of(values_at(columns, u), index++);
      margins.push_back(failure_margin(line, o.margin));
      ++counts[static_cast<int>(sample_status(line))];
      line["margin"] = number_or_infinity(margins.back());
      const std::string text = line.dump() + "\n";
      if (std::fwrite(text.data(), 1, text.size(), out) != text.size())
        throw std::runtime_error("cannot write " + o.samples_path);
    }
    std::fflush(out);
    return margins;
  };
  try {
    c.result = subset_simulation(static_cast<int>(columns.size()), g, o.settings, o.level_done);
  } catch (const std::invalid_argument& e) {
    std::fclose(out);
    throw common::InputError("--method subset", e.what());
  }
  if (std::fclose(out) != 0) throw std::runtime_error("cannot write " + o.samples_path);
  c.counts = json::object();
  for (std::size_t s = 0; s < std::size(kStatusNames); ++s) c.counts[kStatusNames[s]] = counts[s];
  c.counts["total"] = index;
  return c;
}

json subset_summary(const json& plan, const SubsetCampaignOptions& o, const SubsetCampaign& c) {
  const SubsetResult& r = c.result;
  json summary{{"method", "subset"}};
  for (const char* key : {"scene", "scene_sha256", "model", "model_sha256", "uncertain",
                          "uncertain_sha256", "controller", "columns", "nominal"})
    summary[key] = plan.at(key);
  summary["seed"] = o.settings.seed;
  summary["per_level"] = o.settings.per_level;
  summary["p0"] = o.settings.p0;
  summary["max_levels"] = o.settings.max_levels;
  summary["proposal_half_width"] = o.settings.proposal_half_width;
  summary["margin"] = failure_margin_name(o.margin);
  summary["p_unstable"] = {
      {"estimate", r.estimate},
      {"cov", number_or_null(r.cov)},
      {"lo", r.lo},
      {"hi", r.hi},
      {"confidence", 0.95},
      {"interval", r.estimate > 0 ? "lognormal with the estimate as median and the CoV's "
                                    "log-variance ln(1 + cov^2): approximate, asymptotic"
                                  : "no failure at the last level allowed: [0, the probability "
                                    "of the last level's domain]"},
      {"evaluations", r.evaluations},
      {"method", "subset"},
      {"reached_failure", r.reached_failure},
      {"counts", "unstable, refused and error machines as failures"}};
  json levels = json::array();
  for (std::size_t j = 0; j < r.levels.size(); ++j) {
    const SubsetLevel& l = r.levels[j];
    levels.push_back({{"level", j},
                      {"threshold", number_or_infinity(l.threshold)},
                      {"fraction", l.fraction},
                      {"evaluations", l.evaluations},
                      {"acceptance", number_or_null(l.acceptance)},
                      {"gamma", l.gamma},
                      {"cov", number_or_null(l.cov)}});
  }
  summary["levels"] = levels;
  summary["counts"] = c.counts;
  return summary;
}

std::string subset_report_markdown(const json& summary) {
  auto number = [](const json& v) {  // four digits: a table to read, summary.json has them all
    if (v.is_string()) return v.get<std::string>();
    if (!v.is_number()) return std::string("-");
    std::ostringstream s;
    s.precision(4);
    s << v.get<double>();
    return s.str();
  };
  const json& p = summary["p_unstable"];
  std::ostringstream md;
  md << "# Campaign by subset simulation\n\nScene `" << summary["scene"].get<std::string>()
     << "`, uncertain parameters `" << summary["uncertain"].get<std::string>() << "`, controller "
     << summary["controller"].get<std::string>() << ", seed " << summary["seed"] << ".\n\n"
     << "## P(unstable) by subset simulation\n\n**P(unstable)** = " << number(p["estimate"])
     << ", coefficient of variation " << number(p["cov"]) << ", approximate 95 % interval ["
     << number(p["lo"]) << ", " << number(p["hi"]) << "] (" << p["interval"].get<std::string>()
     << "), from " << p["evaluations"] << " evaluations: " << summary["per_level"]
     << " per level, p0 = " << number(summary["p0"]) << ", margin `"
     << summary["margin"].get<std::string>() << "`. Unstable, refused and failed machines count "
     << "as failures (doc/campaign.md, \"Rare failures\")."
     << (p["reached_failure"].get<bool>()
             ? ""
             : " **The level cap was reached before p0 N failures**: the estimate is weak.")
     << "\n\n| level | threshold b | P(g >= b) | evaluations | acceptance | gamma | CoV |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const json& l : summary["levels"])
    md << "| " << l["level"] << " | " << number(l["threshold"]) << " | " << number(l["fraction"])
       << " | " << l["evaluations"] << " | " << number(l["acceptance"]) << " | "
       << number(l["gamma"]) << " | " << number(l["cov"]) << " |\n";
  const json& n = summary["counts"];
  md << "\nEvaluated machines (not a sample of the fleet: the chains seek the failures): "
     << n["total"] << ", of which " << n["stable"] << " stable, " << n["unstable"] << " unstable, "
     << n["marginal"] << " marginal, " << n["refused"] << " refused, " << n["error"]
     << " error (samples.jsonl).\n";
  return md.str();
}

}  // namespace flexloop::campaign
