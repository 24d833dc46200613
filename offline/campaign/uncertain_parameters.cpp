// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/uncertain_parameters.hpp"

#include <cmath>

#include "common/input_error.hpp"
#include "common/toml_reader.hpp"

namespace flexloop::campaign {

namespace {

std::optional<double> optional_number(const common::TomlReader& r, const char* key) {
  if (!r.has(key)) return std::nullopt;
  return r.number(key);
}

double positive_number(const common::TomlReader& r, const char* key) {
  const double v = r.number(key);
  if (!(v > 0)) r.fail("'" + std::string(key) + "' must be positive", r.get(key));
  return v;
}

// The spread of a normal or truncated normal: exactly one of sd and relative_sd.
void read_spread(const common::TomlReader& r, UncertainParameter& p) {
  if (r.has("sd") == r.has("relative_sd"))
    r.fail("give exactly one of 'sd' (absolute) and 'relative_sd' (of the mean)",
           r.get(r.has("sd") ? "sd" : "distribution"));
  if (r.has("sd")) p.sd = positive_number(r, "sd");
  if (r.has("relative_sd")) p.relative_sd = positive_number(r, "relative_sd");
}

void read_distribution(const common::TomlReader& r, UncertainParameter& p) {
  switch (p.kind) {
    case DistributionKind::kUniform:
      r.allow_only({"path", "distribution", "draw", "low", "high"});
      p.low = r.number("low");
      p.high = r.number("high");
      if (!(*p.low < *p.high)) r.fail("'low' must be below 'high'", r.get("high"));
      break;
    case DistributionKind::kNormal:
      r.allow_only({"path", "distribution", "draw", "mean", "sd", "relative_sd"});
      p.mean = optional_number(r, "mean");
      read_spread(r, p);
      break;
    case DistributionKind::kLognormal:
      r.allow_only({"path", "distribution", "draw", "median", "relative_sd"});
      if (r.has("median")) p.median = positive_number(r, "median");
      if (!r.has("relative_sd"))
        r.fail("missing key 'relative_sd' (sd(X) / mean(X) of the lognormal)");
      p.relative_sd = positive_number(r, "relative_sd");
      break;
    case DistributionKind::kTruncatedNormal:
      r.allow_only({"path", "distribution", "draw", "mean", "sd", "relative_sd", "low", "high"});
      p.mean = optional_number(r, "mean");
      read_spread(r, p);
      p.low = optional_number(r, "low");
      p.high = optional_number(r, "high");
      if (!p.low && !p.high)
        r.fail("a truncated_normal needs 'low' or 'high' (or both): without them it is a normal");
      if (p.low && p.high && !(*p.low < *p.high))
        r.fail("'low' must be below 'high'", r.get("high"));
      break;
  }
}

UncertainParameter read_parameter(const common::TomlReader& r) {
  UncertainParameter p;
  p.place = r.place();
  p.path = r.string("path");
  if (p.path.empty()) r.fail("'path' must not be empty", r.get("path"));
  try {
    p.kind = distribution_kind_from_name(r.string("distribution"));
  } catch (const std::invalid_argument& e) {
    r.fail(e.what(), r.get("distribution"));
  }
  const std::string draw = r.string("draw", std::string("each"));
  if (draw != "each" && draw != "shared")
    r.fail(
        "'draw' must be \"each\" (one independent draw per match) or \"shared\" (one draw "
        "for all the matches)",
        r.get("draw"));
  p.draw = draw == "shared" ? DrawMode::kShared : DrawMode::kEach;
  read_distribution(r, p);
  return p;
}

}  // namespace

UncertainParameters parse_uncertain_parameters(const std::string& text, const std::string& file) {
  const toml::table root = common::parse_toml(text, file);
  common::TomlReader top(root, file, "uncertain parameters file");
  top.allow_only({"parameter", "campaign"});
  UncertainParameters u;
  u.file = file;
  if (const auto* c = root.get("campaign")) {
    if (!c->as_table()) top.fail("'campaign' must be a table", c);
    common::TomlReader cr(*c->as_table(), file, "[campaign]");
    cr.allow_only({"controller"});
    u.controller = cr.string("controller", u.controller);
    if (u.controller != "frozen" && u.controller != "redesigned")
      cr.fail(
          "'controller' must be \"frozen\" (the nominal machine's design for every machine) "
          "or \"redesigned\" (the PI designed per machine)",
          cr.get("controller"));
  }
  const auto* list = root.get("parameter");
  if (!list) top.fail("no [[parameter]] entries: nothing is uncertain");
  const auto* arr = list->as_array();
  if (!arr || arr->empty()) top.fail("'parameter' must be a list of [[parameter]] tables", list);
  for (const auto& item : *arr) {
    if (!item.as_table()) top.fail("[[parameter]] entries must be tables", &item);
    u.parameters.push_back(
        read_parameter(common::TomlReader(*item.as_table(), file, "[[parameter]]")));
  }
  return u;
}

UncertainParameters load_uncertain_parameters(const std::string& path) {
  return parse_uncertain_parameters(common::read_input_file(path, "uncertain parameters file"),
                                    path);
}

Distribution distribution_at(const UncertainParameter& p, double nominal) {
  Distribution d;
  d.kind = p.kind;
  auto fail = [&](const std::string& what) {
    throw common::InputError(p.place, "[[parameter]] '" + p.path + "': " + what);
  };
  const double center = p.kind == DistributionKind::kLognormal ? p.median.value_or(nominal)
                                                               : p.mean.value_or(nominal);
  if (p.relative_sd && center == 0)
    fail("relative_sd of a nominal value of zero is no spread: give 'sd' (or a nonzero mean)");
  const double sd = p.sd ? *p.sd : p.relative_sd.value_or(0) * std::abs(center);
  switch (p.kind) {
    case DistributionKind::kUniform:
      d.low = *p.low, d.high = *p.high;
      break;
    case DistributionKind::kNormal:
      d.mean = center, d.sd = sd;
      break;
    case DistributionKind::kLognormal:
      if (!(center > 0))
        fail("a lognormal needs a positive median (the nominal value is " +
             std::to_string(nominal) + ": give 'median')");
      d.median = center;
      d.sigma_log = lognormal_sigma_from_relative_sd(*p.relative_sd);
      break;
    case DistributionKind::kTruncatedNormal:
      d.mean = center, d.sd = sd;
      if (p.low) d.low = *p.low;
      if (p.high) d.high = *p.high;
      break;
  }
  return d;
}

std::string draw_name(DrawMode mode) {
  return mode == DrawMode::kShared ? "shared" : "each";
}

}  // namespace flexloop::campaign
