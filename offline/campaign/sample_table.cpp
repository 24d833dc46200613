// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/sample_table.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <stdexcept>

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

constexpr const char* kScalarFigures[] = {"spectral_radius",     "disk_margin_db",
                                          "disk_margin_deg",     "disk_margin_all_db",
                                          "disk_margin_all_deg", "peak_sigma"};
constexpr const char* kChannelFigures[] = {"rms", "rms_open", "sim.rms", "sim.saturated_share",
                                           "sim.max_abs_command"};

double number_or_nan(const json& j) {
  return j.is_number() ? j.get<double>() : kMissing;
}

// --simulate: a sample's run counted by its status, its relative standard errors kept.
void tally_simulation(const json& sample, SimulationTally& t) {
  const json& sim = field_at(sample, "sim");
  const std::string status = sim.is_object() ? sim.value("status", std::string()) : "";
  if (status == "ran") {
    ++t.ran;
    for (const auto& [channel, rms] : sim["rms"].items()) {
      const json& se = sim["rms_standard_error"][channel];
      if (rms.is_number() && se.is_number() && rms.get<double>() > 0)
        t.relative_standard_error[channel].push_back(se.get<double>() / rms.get<double>());
    }
  } else if (status.rfind("not run", 0) == 0) {
    ++t.not_run;
  } else {
    ++t.error;
  }
}

}  // namespace

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

SampleTableBuilder::SampleTableBuilder(const json& plan)
    : evaluations_(plan.at("evaluations").get<long>()) {
  if (plan.value("design", std::string()) == "saltelli")
    saltelli_stride_ = static_cast<long>(plan.at("columns").size()) + 2;
  if (plan.contains("columns"))
    for (const json& c : plan["columns"]) parameter_paths_.push_back(c.get<std::string>());
  const auto n = static_cast<std::size_t>(evaluations_);
  table_.status.assign(n, SampleStatus::kError);
  table_.parameters.assign(parameter_paths_.size(), std::vector<double>(n, kMissing));
  if (plan.contains("sigma_grid_hz") && plan["sigma_grid_hz"].is_array())
    table_.sigma = ColumnSpill(plan["sigma_grid_hz"].size());
  for (const char* field : kScalarFigures) column(scalars_, field);
}

std::vector<double>& SampleTableBuilder::column(std::map<std::string, std::vector<double>>& columns,
                                                const std::string& name) {
  auto it = columns.find(name);
  if (it == columns.end())
    it =
        columns.emplace(name, std::vector<double>(static_cast<std::size_t>(evaluations_), kMissing))
            .first;
  return it->second;
}

void SampleTableBuilder::add(const json& sample) {
  const long index = sample.value("index", -1L);
  if (index < 0 || index >= evaluations_)
    throw std::invalid_argument("campaign report: a sample of index " + std::to_string(index) +
                                " for a plan of " + std::to_string(evaluations_) + " evaluations");
  const auto i = static_cast<std::size_t>(index);
  table_.status[i] = sample_status(sample);
  if (const json& params = field_at(sample, "parameters"); params.is_object())
    for (std::size_t c = 0; c < parameter_paths_.size(); ++c)
      if (const auto it = params.find(parameter_paths_[c]); it != params.end())
        table_.parameters[c][i] = number_or_nan(*it);
  add_figures(index, sample);
  add_sigma(index, sample);
  tally_simulation(sample, table_.simulation);
}

void SampleTableBuilder::add_figures(long index, const json& sample) {
  const auto i = static_cast<std::size_t>(index);
  for (const char* field : kScalarFigures)
    scalars_[field][i] = figure_value(sample.value(field, json()));
  if (const auto fs = sample.find("natural_frequencies_hz"); fs != sample.end() && fs->is_array())
    for (std::size_t r = 0; r < fs->size(); ++r) {
      if (r == frequencies_.size())
        frequencies_.emplace_back(static_cast<std::size_t>(evaluations_), kMissing);
      frequencies_[r][i] = figure_value((*fs)[r]);
    }
  for (const char* field : kChannelFigures)
    if (const json& obj = field_at(sample, field); obj.is_object())
      for (const auto& [channel, value] : obj.items())
        column(channels_[field], channel)[i] = figure_value(value);
}

// The sigma curve of a stable independent machine, one value per grid frequency it has.
void SampleTableBuilder::add_sigma(long index, const json& sample) {
  const bool machine = saltelli_stride_ == 0 ||
                       (index % saltelli_stride_ < 2 &&
                        index - index % saltelli_stride_ + saltelli_stride_ <= evaluations_);
  const auto s = sample.find("sigma_max");
  if (!machine || table_.status[static_cast<std::size_t>(index)] != SampleStatus::kStable ||
      s == sample.end() || !s->is_array())
    return;
  for (std::size_t j = 0; j < table_.sigma.columns() && j < s->size(); ++j)
    if ((*s)[j].is_number()) table_.sigma.push(j, (*s)[j].get<double>());
}

namespace {

// --simulate's figures (offline/campaign/sample_simulation.hpp): sim.rms.<channel> and its ratio
// to the Lyapunov RMS, sim.rms_ratio.<channel> (the nonlinear effects' share, with the run's
// sampling scatter), sim.saturated_share.<actuator>, sim.max_abs_command.<actuator>.
void simulation_figures(std::map<std::string, std::map<std::string, std::vector<double>>>& channels,
                        std::vector<FigureColumn>& out) {
  for (auto& [c, run] : channels["sim.rms"]) {
    // The Lyapunov RMS of the loop as it ran: the closed loop's, or the passive machine's in an
    // open-loop campaign (no closed-loop RMS there).
    const auto closed = channels["rms"].find(c), open = channels["rms_open"].find(c);
    std::vector<double> ratio(run.size(), kMissing);
    for (std::size_t i = 0; i < run.size(); ++i) {
      const double lc = closed != channels["rms"].end() ? closed->second[i] : kMissing;
      const double lo = open != channels["rms_open"].end() ? open->second[i] : kMissing;
      ratio[i] = run[i] / (std::isnan(lc) ? lo : lc);  // NaN where either is missing
    }
    out.push_back({"sim.rms." + c, std::move(run), Population::kStable});
    out.push_back({"sim.rms_ratio." + c, std::move(ratio), Population::kStable});
  }
  for (const char* field : {"sim.saturated_share", "sim.max_abs_command"})
    for (auto& [c, values] : channels[field])
      out.push_back({std::string(field) + "." + c, std::move(values), Population::kStable});
}

}  // namespace

SampleTable SampleTableBuilder::finish() {
  std::vector<FigureColumn> simulated;  // first: its ratios read the rms columns
  simulation_figures(channels_, simulated);
  std::vector<FigureColumn>& out = table_.figures;
  out.push_back({"spectral_radius", std::move(scalars_["spectral_radius"]), Population::kJudged});
  for (std::size_t r = 0; r < frequencies_.size(); ++r)
    out.push_back({"natural_frequency_" + std::to_string(r + 1) + "_hz", std::move(frequencies_[r]),
                   Population::kJudged});
  for (const char* field : {"rms", "rms_open"})
    for (auto& [c, values] : channels_[field])
      out.push_back({std::string(field) + "." + c, std::move(values),
                     field == std::string("rms_open") ? Population::kJudged : Population::kStable});
  for (const char* field : {"disk_margin_db", "disk_margin_deg", "disk_margin_all_db",
                            "disk_margin_all_deg", "peak_sigma"})
    out.push_back({field, std::move(scalars_[field]), Population::kStable});
  std::move(simulated.begin(), simulated.end(), std::back_inserter(out));
  return std::move(table_);
}

SampleTable sample_table(const json& plan, const std::vector<json>& samples) {
  SampleTableBuilder builder(plan);
  for (const json& s : samples) builder.add(s);
  return builder.finish();
}

MachineTable machine_table(const json& plan, const SampleTable& table) {
  const std::vector<long> machines =
      independent_evaluations(plan, static_cast<long>(table.status.size()));
  MachineTable t;
  for (long i : machines) t.status.push_back(table.status[static_cast<std::size_t>(i)]);
  if (machines.size() == table.status.size()) {  // every evaluation: 0, 1, ..., in order
    t.every_one = &table.figures;
    return t;
  }
  for (const FigureColumn& f : table.figures) {
    FigureColumn picked{f.name, {}, f.population};
    picked.values.reserve(machines.size());
    for (long i : machines) picked.values.push_back(f.values[static_cast<std::size_t>(i)]);
    t.picked.push_back(std::move(picked));
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
