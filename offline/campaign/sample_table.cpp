#include "offline/campaign/sample_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>

namespace flexloop::campaign {

using nlohmann::json;

SampleStatus sample_status(const json& sample) {
  const std::string s = sample.value("status", std::string("error: no status"));
  if (s == "stable") return SampleStatus::kStable;
  if (s == "unstable") return SampleStatus::kUnstable;
  if (s.rfind("refused", 0) == 0) return SampleStatus::kRefused;
  if (s.rfind("marginal", 0) == 0) return SampleStatus::kMarginal;
  return SampleStatus::kError;
}

const char* to_string(Population p) {
  return p == Population::kJudged ? "judged machines (stable, unstable, marginal)"
                                  : "stable machines";
}

double figure_value(const json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const auto& text = j.get_ref<const std::string&>();
    if (text == "+inf") return std::numeric_limits<double>::infinity();
    if (text == "-inf") return -std::numeric_limits<double>::infinity();
  }
  return kMissing;
}

json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

json number_or_infinity(double v) {
  if (std::isinf(v)) return v > 0 ? "+inf" : "-inf";
  return number_or_null(v);
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
  FigureColumn f{field, {}, Population::kStable};
  for (const json& s : samples) f.values.push_back(figure_value(s.value(field, json())));
  return f;
}

FigureColumn channel_figure(const std::vector<json>& samples, const std::string& field,
                            const std::string& channel) {
  FigureColumn f{field + "." + channel, {}, Population::kStable};
  for (const json& s : samples) {
    const json& obj = field_at(s, field);
    f.values.push_back(obj.is_object() && obj.contains(channel) ? figure_value(obj[channel])
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
    // The Lyapunov RMS of the loop as it ran: the closed loop's, or the passive machine's in an
    // open-loop campaign (no closed-loop RMS there).
    const FigureColumn closed = channel_figure(samples, "rms", c);
    const FigureColumn open = channel_figure(samples, "rms_open", c);
    FigureColumn ratio{"sim.rms_ratio." + c, {}, Population::kStable};
    for (std::size_t i = 0; i < run.values.size(); ++i) {
      const double lyapunov = std::isnan(closed.values[i]) ? open.values[i] : closed.values[i];
      ratio.values.push_back(run.values[i] / lyapunov);  // NaN where either is missing
    }
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
    FigureColumn f{"natural_frequency_" + std::to_string(r + 1) + "_hz", {}, Population::kJudged};
    for (const json& s : samples) {
      const json& fs = s.contains("natural_frequencies_hz") ? s["natural_frequencies_hz"] : json();
      f.values.push_back(fs.is_array() && r < fs.size() ? figure_value(fs[r]) : kMissing);
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

std::vector<FigureColumn> figure_columns(const std::vector<json>& samples) {
  std::vector<FigureColumn> out{scalar_figure(samples, "spectral_radius")};
  out.back().population = Population::kJudged;
  for (FigureColumn& f : natural_frequency_figures(samples)) {
    f.population = Population::kJudged;
    out.push_back(std::move(f));
  }
  for (const char* field : {"rms", "rms_open"})
    for (const std::string& c : channels(samples, field)) {
      out.push_back(channel_figure(samples, field, c));
      if (std::string(field) == "rms_open") out.back().population = Population::kJudged;
    }
  for (const char* field : {"disk_margin_db", "disk_margin_deg", "disk_margin_all_db",
                            "disk_margin_all_deg", "peak_sigma"})
    out.push_back(scalar_figure(samples, field));
  for (FigureColumn& f : simulation_figures(samples)) out.push_back(std::move(f));
  return out;
}

std::vector<long> independent_evaluations(const json& plan, long total) {
  std::vector<long> out;
  if (plan.value("design", std::string()) != "saltelli") {
    out.resize(static_cast<std::size_t>(total));
    std::iota(out.begin(), out.end(), 0L);
    return out;
  }
  const auto stride = static_cast<long>(plan.at("columns").size()) + 2;
  for (long b = 0; b + stride <= total; b += stride) {
    out.push_back(b);
    out.push_back(b + 1);
  }
  return out;
}

MachineTable machine_table(const json& plan, const std::vector<json>& samples) {
  const std::vector<long> machines =
      independent_evaluations(plan, static_cast<long>(samples.size()));
  MachineTable t;
  for (long i : machines) t.status.push_back(sample_status(samples[static_cast<std::size_t>(i)]));
  for (FigureColumn& f : figure_columns(samples)) {
    FigureColumn picked{f.name, {}, f.population};
    picked.values.reserve(machines.size());
    for (long i : machines) picked.values.push_back(f.values[static_cast<std::size_t>(i)]);
    t.figures.push_back(std::move(picked));
  }
  return t;
}

std::vector<double> population_values(const FigureColumn& f,
                                      const std::vector<SampleStatus>& status, long prefix) {
  std::vector<double> xs;
  for (long i = 0; i < prefix; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const bool member = f.population == Population::kJudged ? judged(status[k])
                                                            : status[k] == SampleStatus::kStable;
    if (member && !std::isnan(f.values[k])) xs.push_back(f.values[k]);
  }
  return xs;
}

}  // namespace flexloop::campaign
