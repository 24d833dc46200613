// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/planned_parameters.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "common/input_error.hpp"

namespace flexloop::campaign {

namespace {

std::string short_number(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

[[noreturn]] void refuse_parameter(const UncertainParameter& p, const std::string& what) {
  throw common::InputError(p.place, "[[parameter]] '" + p.path + "': " + what);
}

std::vector<std::string> matches_of(const UncertainParameter& p, const MachineDocuments& docs) {
  std::vector<std::string> matches = docs.expand(p.path);
  if (!matches.empty()) return matches;
  std::string near;
  for (const auto& n : nearest_names(p.path, docs.paths())) near += (near.empty() ? "" : ", ") + n;
  refuse_parameter(p, std::string(p.path.find('*') != std::string::npos ? "matches" : "names") +
                          " no number of the model or the scene" +
                          (near.empty() ? std::string(" (the machine has none to vary)")
                                        : "; nearest valid names: " + near) +
                          " (doc/campaign.md lists the paths)");
}

// Every draw of `d` must satisfy the bound: a distribution with an unbounded tail is judged at
// its kTailProbability quantile, the cut beyond which no draw goes.
void require_physical(const UncertainParameter& p, const std::string& path, const Distribution& d,
                      const PhysicalBound& b) {
  if (!std::isfinite(b.lower)) return;
  const double lowest = lowest_draw(d);
  if (lowest > b.lower || (b.lower_inclusive && lowest == b.lower)) return;
  std::string remedy;
  if (d.kind == DistributionKind::kNormal)
    remedy = "; its " + short_number(kTailProbability) +
             " quantile is there: use distribution = \"truncated_normal\" with low = " +
             short_number(b.lower) + ", or a smaller spread";
  else if (d.kind == DistributionKind::kTruncatedNormal)
    remedy = "; set its 'low' to " + short_number(b.lower) + " or above";
  else if (d.kind == DistributionKind::kUniform)
    remedy = "; set 'low' to " + short_number(b.lower) + " or above";
  refuse_parameter(
      p, path + " can be drawn at " + short_number(lowest) + ", but " + b.reason + remedy);
}

}  // namespace

std::vector<PlannedColumn> plan_columns(const UncertainParameters& u, const MachineDocuments& docs,
                                        const std::string& controller) {
  std::vector<PlannedColumn> columns;
  std::map<std::string, std::string> drawn_by;  // concrete path -> place of its entry
  for (std::size_t entry = 0; entry < u.parameters.size(); ++entry) {
    const UncertainParameter& p = u.parameters[entry];
    const std::vector<std::string> matches = matches_of(p, docs);
    if (controller == "frozen" && p.path.rfind("controller.", 0) == 0)
      refuse_parameter(
          p,
          "a controller.* key varies the PI design, but the controller is frozen (designed "
          "once on the nominal machine): set [campaign] controller = \"redesigned\" (or "
          "--controller redesigned) to design it per machine");
    PlannedColumn shared{p.path, entry, {}, {}};
    for (const auto& path : matches) {
      if (const auto [it, fresh] = drawn_by.emplace(path, p.place); !fresh)
        refuse_parameter(p, path + " is drawn already by the entry at " + it->second);
      const ParameterSite& site = docs.site(path);
      const Distribution d = distribution_at(p, site.nominal);
      if (d.kind == DistributionKind::kTruncatedNormal && !(highest_draw(d) > lowest_draw(d)))
        refuse_parameter(
            p, "the truncation [low, high] holds no probability of the normal at " + path);
      require_physical(p, path, d, site.bound);
      if (p.draw == DrawMode::kEach) {
        columns.push_back({path, entry, {path}, {d}});
      } else {
        shared.paths.push_back(path);
        shared.distributions.push_back(d);
      }
    }
    if (p.draw == DrawMode::kShared) columns.push_back(shared);
  }
  return columns;
}

nlohmann::json parameters_json(const UncertainParameters& u,
                               const std::vector<PlannedColumn>& columns) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t entry = 0; entry < u.parameters.size(); ++entry) {
    const UncertainParameter& p = u.parameters[entry];
    nlohmann::json j{{"path", p.path},
                     {"distribution", distribution_name(p.kind)},
                     {"draw", draw_name(p.draw)},
                     {"matches", nlohmann::json::array()},
                     {"match_distributions", nlohmann::json::array()}};
    for (const auto& [key, value] :
         {std::pair{"low", p.low}, std::pair{"high", p.high}, std::pair{"mean", p.mean},
          std::pair{"sd", p.sd}, std::pair{"relative_sd", p.relative_sd},
          std::pair{"median", p.median}})
      if (value) j[key] = *value;
    for (const auto& c : columns)
      for (std::size_t i = 0; c.parameter == entry && i < c.paths.size(); ++i) {
        j["matches"].push_back(c.paths[i]);
        j["match_distributions"].push_back(to_json(c.distributions[i]));
      }
    out.push_back(j);
  }
  return out;
}

nlohmann::json columns_json(const std::vector<PlannedColumn>& columns) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& c : columns) out.push_back(c.name);
  return out;
}

std::vector<PlannedColumn> columns_from_plan(const nlohmann::json& plan) {
  std::map<std::string, PlannedColumn> by_name;
  const auto& parameters = plan.at("parameters");
  for (std::size_t entry = 0; entry < parameters.size(); ++entry) {
    const auto& p = parameters[entry];
    const bool shared = p.at("draw") == "shared";
    const auto& matches = p.at("matches");
    for (std::size_t i = 0; i < matches.size(); ++i) {
      const std::string path = matches[i].get<std::string>();
      PlannedColumn& c = by_name[shared ? p.at("path").get<std::string>() : path];
      c.name = shared ? p.at("path").get<std::string>() : path;
      c.parameter = entry;
      c.paths.push_back(path);
      c.distributions.push_back(distribution_from_json(p.at("match_distributions")[i]));
    }
  }
  std::vector<PlannedColumn> columns;
  for (const auto& name : plan.at("columns"))
    columns.push_back(by_name.at(name.get<std::string>()));
  return columns;
}

ParameterValues values_at(const std::vector<PlannedColumn>& columns, const std::vector<double>& u) {
  ParameterValues values;
  for (std::size_t c = 0; c < columns.size(); ++c)
    for (std::size_t i = 0; i < columns[c].paths.size(); ++i)
      values.emplace_back(columns[c].paths[i], inverse_cdf(columns[c].distributions[i], u.at(c)));
  return values;
}

}  // namespace flexloop::campaign
