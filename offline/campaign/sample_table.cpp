#include "offline/campaign/sample_table.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace flexloop::campaign {

using nlohmann::json;

SampleStatus sample_status(const json& sample) {
  const std::string s = sample.value("status", std::string("error: no status"));
  if (s == "stable") return SampleStatus::kStable;
  if (s == "unstable") return SampleStatus::kUnstable;
  if (s.rfind("refused", 0) == 0) return SampleStatus::kRefused;
  return SampleStatus::kError;
}

namespace {

double number_or_nan(const json& j) {
  return j.is_number() ? j.get<double>() : kMissing;
}

}  // namespace

json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

namespace {

// The channel names of an object field ("rms") over all samples, sorted.
std::set<std::string> channels(const std::vector<json>& samples, const char* field) {
  std::set<std::string> names;
  for (const json& s : samples)
    if (s.contains(field) && s[field].is_object())
      for (const auto& [key, v] : s[field].items()) names.insert(key);
  return names;
}

FigureColumn scalar_figure(const std::vector<json>& samples, const std::string& field) {
  FigureColumn f{field, {}};
  for (const json& s : samples) f.values.push_back(number_or_nan(s.value(field, json())));
  return f;
}

FigureColumn channel_figure(const std::vector<json>& samples, const std::string& field,
                            const std::string& channel) {
  FigureColumn f{field + "." + channel, {}};
  for (const json& s : samples) {
    const json& obj = s.contains(field) ? s[field] : json();
    f.values.push_back(obj.is_object() && obj.contains(channel) ? number_or_nan(obj[channel])
                                                                : kMissing);
  }
  return f;
}

std::vector<FigureColumn> natural_frequency_figures(const std::vector<json>& samples) {
  std::size_t ranks = 0;
  for (const json& s : samples)
    if (s.contains("natural_frequencies_hz") && s["natural_frequencies_hz"].is_array())
      ranks = std::max(ranks, s["natural_frequencies_hz"].size());
  std::vector<FigureColumn> out;
  for (std::size_t r = 0; r < ranks; ++r) {
    FigureColumn f{"natural_frequency_" + std::to_string(r + 1) + "_hz", {}};
    for (const json& s : samples) {
      const json& fs = s.contains("natural_frequencies_hz") ? s["natural_frequencies_hz"] : json();
      f.values.push_back(fs.is_array() && r < fs.size() ? number_or_nan(fs[r]) : kMissing);
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

std::vector<FigureColumn> figure_columns(const std::vector<json>& samples) {
  std::vector<FigureColumn> out{scalar_figure(samples, "spectral_radius")};
  for (FigureColumn& f : natural_frequency_figures(samples)) out.push_back(std::move(f));
  for (const char* field : {"rms", "rms_open"})
    for (const std::string& c : channels(samples, field))
      out.push_back(channel_figure(samples, field, c));
  for (const char* field : {"disk_margin_db", "disk_margin_deg", "disk_margin_all_db",
                            "disk_margin_all_deg", "peak_sigma"})
    out.push_back(scalar_figure(samples, field));
  return out;
}

std::vector<double> stable_values(const FigureColumn& f, const std::vector<SampleStatus>& status,
                                  long prefix) {
  std::vector<double> xs;
  for (long i = 0; i < prefix; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (status[k] == SampleStatus::kStable && std::isfinite(f.values[k])) xs.push_back(f.values[k]);
  }
  return xs;
}

}  // namespace flexloop::campaign
