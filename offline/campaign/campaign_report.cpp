// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/campaign_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "offline/campaign/campaign_pictures.hpp"
#include "offline/campaign/designs.hpp"
#include "offline/campaign/sample_table.hpp"
#include "offline/campaign/statistics.hpp"
#include "offline/scene/loop_artefact_builder.hpp"

namespace flexloop::campaign {

namespace {

using nlohmann::json;
constexpr double kConfidence = 0.95;
constexpr double kProbabilities[] = {0.05, 0.5, 0.95};

// n = 1, 2, 4, ... below `total`, then total.
std::vector<long> prefixes(long total) {
  std::vector<long> out;
  for (long n = 1; n < total; n *= 2) out.push_back(n);
  if (total > 0) out.push_back(total);
  return out;
}

json quantile_json(const QuantileInterval& q) {
  return {{"p", q.p},
          {"estimate", number_or_infinity(q.estimate)},
          {"lo", number_or_null(q.lo)},
          {"hi", number_or_null(q.hi)},
          {"confidence", q.confidence}};
}

json quantiles_json(const std::vector<double>& xs) {
  json out = json::array();
  for (double p : kProbabilities)
    out.push_back(quantile_json(quantile_interval(xs, p, kConfidence)));
  return out;
}

bool starts_with(const std::string& s, const char* prefix) {
  return s.rfind(prefix, 0) == 0;
}

// The SI unit of a figure ("1": a ratio); a channel's figure takes its channel's unit.
std::string figure_unit(const std::string& name) {
  for (const char* prefix : {"rms.", "rms_open.", "sim.rms.", "sim.max_abs_command."})
    if (starts_with(name, prefix)) return scene::channel_unit(name.substr(std::strlen(prefix)));
  if (starts_with(name, "natural_frequency_")) return "Hz";
  if (starts_with(name, "disk_margin"))
    return name.size() > 3 && name.substr(name.size() - 3) == "_db" ? "dB" : "deg";
  if (name == "peak_sigma") return "performance unit per floor unit";
  return "1";  // spectral_radius, sim.rms_ratio.*, sim.saturated_share.*
}

// The figures only a closed loop has: its RMS and its disk margins.
bool closed_loop_figure(const std::string& name) {
  return starts_with(name, "rms.") || starts_with(name, "disk_margin");
}

json figure_summary(const FigureColumn& f, const std::vector<SampleStatus>& status) {
  const auto total = static_cast<long>(status.size());
  const std::vector<double> xs = population_values(f, status, total);
  json out{{"n", xs.size()},
           {"unit", figure_unit(f.name)},
           {"population", to_string(f.population)},
           {"quantiles", quantiles_json(xs)}};
  out["min"] =
      xs.empty() ? json(nullptr) : number_or_infinity(*std::min_element(xs.begin(), xs.end()));
  out["max"] =
      xs.empty() ? json(nullptr) : number_or_infinity(*std::max_element(xs.begin(), xs.end()));
  json convergence = json::array();
  for (long prefix : prefixes(total)) {
    const std::vector<double> ys = population_values(f, status, prefix);
    convergence.push_back({{"n", prefix}, {"used", ys.size()}, {"quantiles", quantiles_json(ys)}});
  }
  out["convergence"] = convergence;
  return out;
}

json p_unstable_json(const std::vector<SampleStatus>& status, long prefix) {
  long unstable = 0, judged = 0;
  for (long i = 0; i < prefix; ++i) {
    const SampleStatus s = status[static_cast<std::size_t>(i)];
    unstable += s == SampleStatus::kUnstable;
    judged += campaign::judged(s);
  }
  const Interval ci = clopper_pearson(unstable, judged, kConfidence);
  return {{"n", prefix},
          {"samples", prefix},
          {"unstable", unstable},
          {"judged", judged},
          {"estimate", number_or_null(ci.estimate)},
          {"lo", ci.lo},
          {"hi", ci.hi},
          {"confidence", kConfidence},
          {"method", "clopper-pearson"}};
}

// Every machine that is not shown stable, refused (buckled, statically unstable) and failed ones
// included, over all the independent machines: what a fleet loses, where P(unstable) is the
// share of the judged machines.
json p_not_stable_json(const std::vector<SampleStatus>& status) {
  const auto all = static_cast<long>(status.size());
  const long not_stable = all - std::count(status.begin(), status.end(), SampleStatus::kStable);
  const Interval ci = clopper_pearson(not_stable, all, kConfidence);
  return {{"samples", all},
          {"not_stable", not_stable},
          {"estimate", number_or_null(ci.estimate)},
          {"lo", ci.lo},
          {"hi", ci.hi},
          {"confidence", kConfidence},
          {"method", "clopper-pearson"}};
}

json counts_json(const std::vector<SampleStatus>& status) {
  long counts[std::size(kStatusNames)] = {};
  for (SampleStatus s : status) ++counts[static_cast<int>(s)];
  json out{{"total", status.size()}};
  for (std::size_t k = 0; k < std::size(kStatusNames); ++k) out[kStatusNames[k]] = counts[k];
  return out;
}

json interval_json(const Interval& i, bool holds_zero) {
  return {{"estimate", number_or_null(i.estimate)},
          {"lo", number_or_null(i.lo)},
          {"hi", number_or_null(i.hi)},
          {"holds_zero", holds_zero}};
}

// Sobol indices of one figure: the base rows whose d + 2 evaluations all have the figure.
json sobol_figure_json(const FigureColumn& f, long n, const std::vector<std::string>& columns) {
  const int d = static_cast<int>(columns.size());
  const long stride = d + 2L;
  std::vector<double> y;
  long rows = 0;
  for (long b = 0; b < n; ++b) {
    const auto first = f.values.begin() + b * stride;
    if (!std::all_of(first, first + stride, [](double v) { return std::isfinite(v); })) continue;
    y.insert(y.end(), first, first + stride);
    ++rows;
  }
  json out{{"base_rows", rows}, {"dropped_rows", n - rows}, {"parameters", json::array()}};
  if (rows < 2) return out;
  const std::vector<SobolIndex> indices = sobol_indices(y, rows, d, 500, 1, kConfidence);
  for (int i = 0; i < d; ++i) {
    const SobolIndex& s = indices[static_cast<std::size_t>(i)];
    out["parameters"].push_back({{"path", columns[static_cast<std::size_t>(i)]},
                                 {"first", interval_json(s.first, s.first_holds_zero)},
                                 {"total", interval_json(s.total, s.total_holds_zero)}});
  }
  return out;
}

std::vector<std::string> column_paths(const json& plan) {
  std::vector<std::string> columns;
  for (const json& c : plan.at("columns")) columns.push_back(c.get<std::string>());
  return columns;
}

std::string population_text(const json& plan) {
  return plan.value("design", std::string()) == "saltelli"
             ? "the A and B rows of the Saltelli design (2n independent machines; its A_B^i rows "
               "share all but one parameter with their A row and serve the Sobol indices only)"
             : "every evaluation";
}

void check_samples(const json& plan, const std::vector<json>& samples) {
  const long evaluations = plan.at("evaluations").get<long>();
  if (static_cast<long>(samples.size()) != evaluations)
    throw std::invalid_argument("campaign report: " + std::to_string(samples.size()) +
                                " samples for a plan of " + std::to_string(evaluations) +
                                " evaluations");
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].value("index", -1L) != static_cast<long>(i))
      throw std::invalid_argument("campaign report: sample " + std::to_string(i) + " has index " +
                                  samples[i].value("index", json()).dump());
}

void check_saltelli_size(const json& plan, long total) {
  if (plan.value("design", std::string()) != "saltelli") return;
  const long n = plan.at("n").get<long>();
  const auto d = static_cast<int>(column_paths(plan).size());
  if (total != evaluation_count(DesignKind::kSaltelli, n, d))
    throw std::invalid_argument("campaign report: a Saltelli plan of n = " + std::to_string(n) +
                                " and " + std::to_string(d) +
                                " columns has another number of evaluations");
}

// The median of finite values, NaN for none.
double median(std::vector<double> xs) {
  if (xs.empty()) return std::nan("");
  std::sort(xs.begin(), xs.end());
  const std::size_t m = xs.size() / 2;
  return xs.size() % 2 ? xs[m] : (xs[m - 1] + xs[m]) / 2;
}

// --simulate: the runs' counts by status and, per performance channel, the median relative
// standard error of the simulated RMS (the scatter a ratio sim / Lyapunov has from the run's
// length alone). Null for a plan without simulation.
json simulation_summary(const json& plan, const SimulationTally& t) {
  if (!plan.contains("simulate_s")) return nullptr;
  json channels = json::object();
  for (const auto& [channel, xs] : t.relative_standard_error)
    channels[channel] = {{"median_relative_standard_error", number_or_null(median(xs))}};
  return {{"seconds", plan["simulate_s"]},
          {"ran", t.ran},
          {"not_run", t.not_run},
          {"error", t.error},
          {"channels", channels}};
}

// For a Saltelli plan: per figure (over every evaluation) the Sobol indices, and those of the
// indicator 1{unstable}.
json sobol_json(const json& plan, const SampleTable& table) {
  const std::vector<std::string> columns = column_paths(plan);
  const long n = plan.at("n").get<long>();
  json sobol = json::object();
  for (const FigureColumn& f : table.figures) sobol[f.name] = sobol_figure_json(f, n, columns);
  // Which parameter drives P(unstable): the indices of the indicator 1{unstable} (judged
  // machines; a refused or failed one drops its block like a missing figure).
  FigureColumn unstable{"unstable", {}, Population::kJudged};
  unstable.values.reserve(table.status.size());
  for (SampleStatus st : table.status)
    unstable.values.push_back(judged(st) ? (st == SampleStatus::kUnstable ? 1.0 : 0.0) : kMissing);
  sobol["unstable"] = sobol_figure_json(unstable, n, columns);
  return sobol;
}

}  // namespace

json campaign_summary(const json& plan, const std::vector<json>& samples) {
  check_samples(plan, samples);
  const SampleTable table = sample_table(plan, samples);
  return campaign_summary(plan, table, machine_table(plan, table));
}

json campaign_summary(const json& plan, const SampleTable& table, const MachineTable& machines) {
  const std::vector<SampleStatus>& status = table.status;
  const auto total = static_cast<long>(status.size());
  check_saltelli_size(plan, total);
  // Figures and intervals over independent machines only (doc/campaign_statistics.md).
  const std::vector<SampleStatus>& machine_status = machines.status;
  const auto m = static_cast<long>(machine_status.size());
  json summary{{"format", "flexloop-campaign-summary"},
               {"version", 1},
               {"plan_id", plan.value("plan_id", json())},
               {"design", plan.value("design", json())},
               {"n", plan.value("n", json())},
               {"evaluations", total},
               {"confidence", kConfidence},
               {"counts", counts_json(status)},
               {"machines", {{"count", m}, {"population", population_text(plan)}}},
               {"p_unstable", p_unstable_json(machine_status, m)},
               {"p_not_stable", p_not_stable_json(machine_status)}};
  json convergence = json::array();
  for (long prefix : prefixes(m)) convergence.push_back(p_unstable_json(machine_status, prefix));
  summary["p_unstable_convergence"] = convergence;
  const bool open_loop = plan.value("loop", std::string("closed")) == "open";
  summary["loop"] = open_loop ? "open" : "closed";
  json per_figure = json::object(), order = json::array();
  for (const FigureColumn& f : machines.figures()) {
    if (open_loop && closed_loop_figure(f.name)) continue;  // no loop: the figure is not defined
    per_figure[f.name] = figure_summary(f, machine_status);
    order.push_back(f.name);
  }
  summary["figures"] = per_figure;
  summary["figure_order"] = order;  // JSON objects have no order; the report's tables keep this
  if (const json sim = simulation_summary(plan, table.simulation); !sim.is_null())
    summary["simulation"] = sim;
  if (plan.value("design", std::string()) == "saltelli") summary["sobol"] = sobol_json(plan, table);
  return summary;
}

namespace {

// A number for a table: 4 significant digits; "-inf"/"+inf" for an unbounded end, "-" for none.
std::string cell(const json& v, const char* unbounded = "-") {
  if (v.is_string()) return v.get<std::string>();  // "+inf" / "-inf": an infinite order statistic
  if (!v.is_number()) return unbounded;
  std::ostringstream s;
  s.precision(4);
  s << v.get<double>();
  return s.str();
}

std::string quantile_cell(const json& q) {
  return cell(q["estimate"]) + " [" + cell(q["lo"], "-inf") + ", " + cell(q["hi"], "+inf") + "]";
}

// With no failure the interval's lower end is 0 by definition and its upper end is the one-sided
// 97.5 % bound 1 - 0.025^(1/m); the one-sided 95 % bound 1 - 0.05^(1/m) is the usual claim.
std::string zero_failures_note(long failures, long m) {
  if (failures != 0 || m == 0) return "";
  std::ostringstream md;
  md << "With none unstable the interval is one-sided: its upper end is the 97.5 % upper bound; "
     << "the one-sided 95 % upper bound is 1 - 0.05^(1/" << m
     << ") = " << cell(json(1 - std::pow(0.05, 1.0 / static_cast<double>(m)))) << ".\n\n";
  return md.str();
}

// Which interval is valid for how the design drew its machines (doc/campaign_statistics.md).
std::string design_interval_note(const json& design) {
  const std::string d = design.is_string() ? design.get<std::string>() : "";
  if (d == "random") return "The design draws independent machines: the intervals hold as stated.";
  if (d == "lhs")
    return "A Latin hypercube spreads its machines more evenly than independent draws: the "
           "intervals below, computed as for independent machines, are conservative.";
  return "This design's points are deterministic (unscrambled Sobol points): no confidence "
         "interval applies; the intervals below are what independent machines would give. Use "
         "the random or lhs design for a confidence statement.";
}

std::string counts_markdown(const json& summary) {
  const json& c = summary["counts"];
  const json& p = summary["p_unstable"];
  const json& q = summary["p_not_stable"];
  std::ostringstream md;
  md << "## Samples\n\n| evaluations | stable | unstable | marginal | refused | error "
        "|\n|---|---|---|---|---|---|\n"
     << "| " << c["total"] << " | " << c["stable"] << " | " << c["unstable"] << " | "
     << c["marginal"] << " | " << c["refused"] << " | " << c["error"] << " |\n\n"
     << "Figures and intervals are over " << summary["machines"]["population"].get<std::string>()
     << ": " << summary["machines"]["count"] << " machines. "
     << design_interval_note(summary["design"]) << "\n\n"
     << "**P(unstable)** = " << cell(p["estimate"]) << ", Clopper-Pearson 95 % interval ["
     << cell(p["lo"]) << ", " << cell(p["hi"]) << "] (" << p["unstable"] << " unstable of "
     << p["judged"] << " judged: stable, unstable or marginal).\n\n"
     << zero_failures_note(p["unstable"].get<long>(), p["judged"].get<long>())
     << "**P(not stable)** = " << cell(q["estimate"]) << ", Clopper-Pearson 95 % interval ["
     << cell(q["lo"]) << ", " << cell(q["hi"]) << "] (" << q["not_stable"] << " of " << q["samples"]
     << " machines unstable, marginal, refused or failed).\n\n";
  return md.str();
}

std::string figures_markdown(const json& summary) {
  std::ostringstream md;
  md << "## Figures\n\n"
     << "Each cell: the quantile's estimate [its distribution-free interval, confidence >= 95 "
        "%]; an unbounded end means too few samples for that confidence, +inf an unbounded "
        "figure (a disk margin no gain increase reaches). Each figure is over the machines that "
        "have it: the spectral radius, natural frequencies and open-loop RMS over every judged "
        "machine (stable or unstable), the closed loop's figures over the stable ones.\n\n"
     << "| figure | over | n | 5 % | 50 % | 95 % |\n|---|---|---|---|---|---|\n";
  for (const json& name : summary["figure_order"]) {
    const json& f = summary["figures"][name.get<std::string>()];
    md << "| " << name.get<std::string>() << " [" << f["unit"].get<std::string>() << "] | "
       << (f["population"] == "stable machines" ? "stable" : "judged") << " | " << f["n"];
    for (const json& q : f["quantiles"]) md << " | " << quantile_cell(q);
    md << " |\n";
  }
  return md.str() + "\n";
}

// --simulate: how far the simulated RMS is from the Lyapunov RMS (the nonlinear effects' share),
// against the scatter the run's length alone gives it.
std::string simulation_markdown(const json& summary) {
  if (!summary.contains("simulation")) return "";
  const json& sim = summary["simulation"];
  const json& figures = summary["figures"];
  std::ostringstream md;
  md << "## Simulated runs against the Lyapunov RMS\n\n"
     << "Each stable sample's loop ran for " << cell(sim["seconds"]) << " s with `flexloop "
     << "sim`'s code and every effect of the scene (saturation, the ADC's rounding, delays, "
     << "noise): " << sim["ran"] << " ran, " << sim["not_run"]
     << " not run (a loop not stable, a sample refused), " << sim["error"]
     << " failed. The Lyapunov RMS is the loop made linear (no saturation, the "
     << "ADC's rounding as uniform noise); the ratio simulated / Lyapunov RMS shows the "
     << "nonlinear effects, beside the scatter the run's length alone gives it (the simulated "
     << "RMS's relative standard error, by batch means: a ratio within 1 +- 2 of it is that "
     << "scatter, not an effect).\n\n"
     << "| channel | n | ratio 5 % | ratio 50 % | ratio 95 % | relative standard error "
        "(median) |\n|---|---|---|---|---|---|\n";
  for (const auto& [channel, c] : sim["channels"].items()) {
    const std::string name = "sim.rms_ratio." + channel;
    if (!figures.contains(name)) continue;
    const json& f = figures[name];
    md << "| " << channel << " | " << f["n"];
    for (const json& q : f["quantiles"]) md << " | " << quantile_cell(q);
    md << " | " << cell(c["median_relative_standard_error"]) << " |\n";
  }
  md << "\nThe share of samples at the actuator's limit and the largest command are the "
        "figures `sim.saturated_share.<actuator>` and `sim.max_abs_command.<actuator>` above.\n\n";
  return md.str();
}

std::string sobol_markdown(const json& summary) {
  if (!summary.contains("sobol")) return "";
  std::ostringstream md;
  md << "## Sobol indices (Saltelli design)\n\n"
     << "First order (Saltelli 2010) and total (Jansen) with 95 % bootstrap intervals; "
        "(0) marks an interval that holds 0. `unstable` is the indicator of an unstable loop: "
        "which parameter drives P(unstable). A base row is used only when all its d + 2 "
        "evaluations have the figure; the others are dropped, which conditions the inputs on "
        "the figure existing.\n\n"
     << "| figure | base rows used | dropped |\n|---|---|---|\n";
  std::vector<std::string> names{"unstable"}, warned;
  for (const json& name : summary["figure_order"]) names.push_back(name.get<std::string>());
  for (const std::string& name : names) {
    const json& f = summary["sobol"][name];
    const long used = f["base_rows"].get<long>(), dropped = f["dropped_rows"].get<long>();
    md << "| " << name << " | " << used << " | " << dropped << " |\n";
    if (dropped > 0.05 * static_cast<double>(used + dropped)) warned.push_back(name);
  }
  md << "\n";
  for (const std::string& name : warned)
    md << "**Warning:** " << name << " dropped more than 5 % of its base rows: its indices "
       << "describe the machines that have it, not the whole box.\n\n";
  md << "| figure | parameter | first | total |\n|---|---|---|---|\n";
  const auto index = [](const json& i) {
    return cell(i["estimate"]) + " [" + cell(i["lo"]) + ", " + cell(i["hi"]) + "]" +
           (i["holds_zero"].get<bool>() ? " (0)" : "");
  };
  for (const std::string& name : names)
    for (const json& p : summary["sobol"][name]["parameters"])
      md << "| " << name << " | " << p["path"].get<std::string>() << " | " << index(p["first"])
         << " | " << index(p["total"]) << " |\n";
  return md.str() + "\n";
}

// An open-loop campaign says what its verdicts and figures are of: the passive machine.
std::string loop_markdown(const json& summary) {
  if (summary.value("loop", std::string()) != "open") return "";
  return "**Open loop:** the scene has no controller, so this campaign judges the passive "
         "machine alone: its sampled plant's spectral radius (unstable above the unit circle, "
         "marginal without a stationary state), its natural frequencies, its RMS under the "
         "scene's floor and noise (`rms_open`) and the floor -> performance path's largest "
         "singular value (`peak_sigma`). It has no closed-loop RMS and no disk margins.\n\n";
}

std::string report_markdown(const json& summary, const std::vector<Picture>& pictures) {
  std::ostringstream md;
  md << "# Campaign report\n\nPlan " << summary["plan_id"].dump() << ", design "
     << summary["design"].dump() << ", n = " << summary["n"].dump() << " ("
     << summary["evaluations"] << " evaluations). The numbers are in summary.json; the "
     << "estimators are described in doc/campaign_statistics.md of flexloop.\n\n"
     << loop_markdown(summary) << counts_markdown(summary) << figures_markdown(summary)
     << simulation_markdown(summary) << sobol_markdown(summary) << "## Pictures\n\n";
  for (const Picture& p : pictures)
    md << "### " << p.caption << "\n\n![" << p.caption << "](" << p.file << ")\n\n";
  return md.str();
}

}  // namespace

void write_campaign_report(const json& plan, const SampleTable& table, const std::string& out_dir) {
  const MachineTable machines = machine_table(plan, table);
  const json summary = campaign_summary(plan, table, machines);
  std::filesystem::create_directories(out_dir);
  const std::vector<Picture> pictures =
      draw_campaign_pictures(plan, table, machines, summary, out_dir);
  common::write_text_atomically(std::filesystem::path(out_dir) / "summary.json",
                                summary.dump(2) + "\n");
  common::write_text_atomically(std::filesystem::path(out_dir) / "report.md",
                                report_markdown(summary, pictures));
}

void write_campaign_report(const json& plan, const std::vector<json>& samples,
                           const std::string& out_dir) {
  check_samples(plan, samples);
  write_campaign_report(plan, sample_table(plan, samples), out_dir);
}

}  // namespace flexloop::campaign
