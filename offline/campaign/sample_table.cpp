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

// The value at a dotted field path of a sample ("rms", "sim.rms"), null when it has none.
const json& field_at(const json& sample, const std::string& field) {
  static const json kNone;
  const json* at = &sample;
  for (std::size_t begin = 0; begin <= field.size();) {
    const std::size_t end = std::min(field.find('.', begin), field.size());
    const std::string key = field.substr(begin, end - begin);
    if (!at->is_object() || !at->contains(key)) return kNone;
    at = &(*at)[key];
    begin = end + 1;
  }
  return *at;
}

// The channel names of an object field ("rms", "sim.rms") over all samples, sorted.
std::set<std::string> channels(const std::vector<json>& samples, const std::string& field) {
  std::set<std::string> names;
  for (const json& s : samples)
    if (const json& obj = field_at(s, field); obj.is_object())
      for (const auto& [key, v] : obj.items()) names.insert(key);
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
    const json& obj = field_at(s, field);
    f.values.push_back(obj.is_object() && obj.contains(channel) ? number_or_nan(obj[channel])
                                                                : kMissing);
  }
  return f;
}

// --simulate's figures (offline/campaign/sample_simulation.hpp): sim.rms.<channel> and its ratio
// to the Lyapunov RMS, sim.rms_ratio.<channel> (the nonlinear effects' share, with the run's
// sampling scatter), sim.saturated_share.<actuator>, sim.max_abs_command.<actuator>.
std::vector<FigureColumn> simulation_figures(const std::vector<json>& samples) {
  std::vector<FigureColumn> out;
  for (const std::string& c : channels(samples, "sim.rms")) {
    FigureColumn run = channel_figure(samples, "sim.rms", c);
    const FigureColumn lyapunov = channel_figure(samples, "rms", c);
    FigureColumn ratio{"sim.rms_ratio." + c, {}};
    for (std::size_t i = 0; i < run.values.size(); ++i)
      ratio.values.push_back(run.values[i] / lyapunov.values[i]);  // NaN where either is missing
    out.push_back(std::move(run));
    out.push_back(std::move(ratio));
  }
  for (const char* field : {"sim.saturated_share", "sim.max_abs_command"})
    for (const std::string& c : channels(samples, field))
      out.push_back(channel_figure(samples, field, c));
  return out;
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
  for (FigureColumn& f : simulation_figures(samples)) out.push_back(std::move(f));
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
