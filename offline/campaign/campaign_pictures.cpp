// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/campaign_pictures.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "offline/campaign/sample_table.hpp"
#include "offline/campaign/statistics.hpp"
#include "offline/report/plot.hpp"

namespace flexloop::campaign {

namespace {

using nlohmann::json;
constexpr int kHistogramRanks = 3;  // the first natural frequencies drawn as histograms

// A figure's name as part of a file name.
std::string file_stem(const std::string& name) {
  std::string s;
  for (char c : name)
    s +=
        (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.') ? c : '_';
  return s;
}

double json_or_nan(const json& j) {
  return j.is_number() ? j.get<double>() : kMissing;
}

// The ECDF of xs (sorted here) as a staircase, each quantile's estimate and its interval as a
// horizontal bar at height p (an unbounded end drawn to the data's end, dashed). Infinite values
// (an unbounded margin) count in the heights but cannot be drawn: the staircase ends below 1.
// None when no value is finite.
std::optional<report::PlotScript> ecdf_script(const std::string& name, std::vector<double> xs,
                                              const char* population, const json& quantiles,
                                              const std::string& png) {
  std::sort(xs.begin(), xs.end());
  std::vector<double> finite;
  std::copy_if(xs.begin(), xs.end(), std::back_inserter(finite),
               [](double x) { return std::isfinite(x); });
  if (finite.empty()) return std::nullopt;
  report::Series ecdf{"ECDF of " + std::to_string(xs.size()) + " " + population,
                      {finite.front()},
                      {0.0},
                      "steps lw 2 lc rgb '#1f4e79'"};
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (!std::isfinite(xs[i])) continue;
    ecdf.x.push_back(xs[i]);
    ecdf.y.push_back(static_cast<double>(i + 1) / static_cast<double>(xs.size()));
  }
  std::vector<report::Series> series{ecdf};
  for (const json& q : quantiles) {
    const double p = q["p"].get<double>();
    const bool bounded = q["lo"].is_number() && q["hi"].is_number();
    const double lo = q["lo"].is_number() ? q["lo"].get<double>() : finite.front();
    const double hi = q["hi"].is_number() ? q["hi"].get<double>() : finite.back();
    const std::string pct = std::to_string(static_cast<int>(std::lround(100 * p)));
    series.push_back(
        {pct + " % quantile, " + (bounded ? "its 95 % interval" : "its interval (unbounded)"),
         {lo, hi},
         {p, p},
         std::string("linespoints lw 4 pt 2 ps 1.5 lc rgb '#d62728'") + (bounded ? "" : " dt 2")});
    series.push_back(
        {"", {json_or_nan(q["estimate"])}, {p}, "points pt 7 ps 1.6 lc rgb '#000000'"});
  }
  report::PlotSpec spec;
  spec.title = name + ": empirical distribution with the 5/50/95 % quantile intervals";
  spec.xlabel = name;
  spec.ylabel = std::string("fraction of the ") + population + " <= x";
  if (finite.front() == finite.back()) {  // one value: an axis of +-0.5 % around it
    const double half = finite.front() != 0.0 ? 0.005 * std::abs(finite.front()) : 0.5;
    spec.x_min = finite.front() - half, spec.x_max = finite.front() + half;
  }
  return report::lines_script(spec, series, png);
}

report::PlotScript histogram_script(const std::string& name, const std::vector<double>& xs,
                                    const std::string& png) {
  const auto [min_it, max_it] = std::minmax_element(xs.begin(), xs.end());
  double lo = *min_it, hi = *max_it;
  if (!(hi > lo)) {  // one value: a bin of +-0.5 % around it
    const double half = lo != 0.0 ? 0.005 * std::abs(lo) : 0.5;
    lo -= half, hi += half;
  }
  const int bins = std::clamp(static_cast<int>(std::ceil(std::sqrt(xs.size()))), 5, 50);
  std::vector<double> edges, counts(static_cast<std::size_t>(bins), 0.0);
  for (int b = 0; b <= bins; ++b) edges.push_back(lo + (hi - lo) * b / bins);
  for (double x : xs) {
    const int b = std::min(bins - 1, static_cast<int>((x - lo) / (hi - lo) * bins));
    counts[static_cast<std::size_t>(std::max(0, b))] += 1.0;
  }
  report::PlotSpec spec;
  spec.title = name + ": histogram over " + std::to_string(xs.size()) + " stable samples";
  spec.xlabel = "frequency [Hz]";
  spec.ylabel = "samples";
  return report::histogram_script(spec, edges, counts, png);
}

// The order statistic x_(k) of xs (k = max(1, ceil(p n))): the ECDF's inverse at p. Moves xs's
// elements (nth_element), which keeps every x_(j) of j > k above it.
double order_statistic(std::vector<double>& xs, std::size_t end, double p) {
  const auto k = static_cast<std::size_t>(
      std::max(1L, static_cast<long>(std::ceil(p * static_cast<double>(xs.size())))));
  std::nth_element(xs.begin(), xs.begin() + static_cast<long>(k - 1),
                   xs.begin() + static_cast<long>(end));
  return xs[k - 1];
}

// Per grid point: 5/50/95 % (ECDF inverse) and the max of sigma_max over the stable machines
// (the independent evaluations, as the summary's figures), one frequency's values at a time.
std::optional<report::PlotScript> sigma_envelope_script(const json& plan, const ColumnSpill& sigma,
                                                        const std::string& png) {
  if (!plan.contains("sigma_grid_hz") || !plan["sigma_grid_hz"].is_array()) return std::nullopt;
  const std::vector<double> f = plan["sigma_grid_hz"].get<std::vector<double>>();
  const auto db = [](double s) { return s > 0.0 ? 20.0 * std::log10(s) : kMissing; };
  std::vector<report::Series> lines{{"max over samples", f, {}, "lines lw 2 lc rgb '#d62728'"},
                                    {"95 %", f, {}, "lines lw 2 lc rgb '#ff7f0e'"},
                                    {"50 %", f, {}, "lines lw 2 lc rgb '#2ca02c'"},
                                    {"5 %", f, {}, "lines lw 2 lc rgb '#1f77b4'"}};
  bool any = false;
  for (std::size_t j = 0; j < f.size(); ++j) {
    std::vector<double> at = sigma.column(j);
    any = any || !at.empty();
    if (at.empty()) {
      for (auto& l : lines) l.y.push_back(kMissing);
      continue;
    }
    // Largest rank first: each selection leaves the ranks below it in front of it.
    lines[0].y.push_back(db(*std::max_element(at.begin(), at.end())));
    const double q95 = order_statistic(at, at.size(), 0.95);
    const auto k95 = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(at.size())));
    const double q50 = order_statistic(at, std::max<std::size_t>(1, k95), 0.5);
    const auto k50 = static_cast<std::size_t>(std::ceil(0.5 * static_cast<double>(at.size())));
    const double q05 = order_statistic(at, std::max<std::size_t>(1, k50), 0.05);
    lines[1].y.push_back(db(q95));
    lines[2].y.push_back(db(q50));
    lines[3].y.push_back(db(q05));
  }
  if (!any) return std::nullopt;
  const json& nominal = plan.contains("nominal") ? plan["nominal"] : json();
  if (nominal.is_object() && nominal.contains("sigma_max") && nominal["sigma_max"].is_array() &&
      nominal["sigma_max"].size() == f.size()) {
    report::Series nom{"nominal machine", f, {}, "lines lw 2 dt 2 lc rgb '#000000'"};
    for (const json& s : nominal["sigma_max"]) nom.y.push_back(db(json_or_nan(s)));
    lines.push_back(nom);
  }
  report::PlotSpec spec;
  spec.title = "closed loop, floor -> performance: largest singular value over the samples";
  spec.xlabel = "frequency [Hz]";
  spec.ylabel = "sigma_max [dB]";
  spec.logx = true;
  return report::lines_script(spec, lines, png);
}

const std::vector<double>& figure_values(const SampleTable& table, const std::string& name) {
  static const std::vector<double> kNone;
  for (const FigureColumn& f : table.figures)
    if (f.name == name) return f.values;
  return kNone;
}

// The worst figures against one parameter (column c of the plan): the disk margin and the peak
// sigma of the stable samples, and the spectral radius of every judged sample (unstable ones in
// red, above 1), over every evaluation.
std::optional<report::PlotScript> scatter_script(const std::string& column, std::size_t c,
                                                 const SampleTable& table, const std::string& png) {
  const std::vector<double>& xs = table.parameters[c];
  const auto figure = [&](const char* field, bool stable, bool unstable) {
    report::Series s{"", {}, {}, "points pt 7 ps 0.6 lc rgb '#1f4e79'"};
    const std::vector<double>& ys = figure_values(table, field);
    for (std::size_t i = 0; i < table.status.size() && i < ys.size(); ++i) {
      const bool wanted = (stable && table.status[i] == SampleStatus::kStable) ||
                          (unstable && table.status[i] == SampleStatus::kUnstable);
      if (wanted && std::isfinite(xs[i]) && std::isfinite(ys[i]))
        s.x.push_back(xs[i]), s.y.push_back(ys[i]);
    }
    return s;
  };
  report::Series radius_stable = figure("spectral_radius", true, false);
  report::Series radius_unstable = figure("spectral_radius", false, true);
  radius_stable.title = "stable";
  radius_unstable.title = "unstable";
  radius_unstable.style = "points pt 2 ps 0.9 lc rgb '#d62728'";
  std::vector<report::Panel> panels{{"disk margin [dB]", {figure("disk_margin_db", true, false)}},
                                    {"peak sigma", {figure("peak_sigma", true, false)}},
                                    {"spectral radius", {radius_stable}}};
  if (!radius_unstable.x.empty()) panels.back().series.push_back(radius_unstable);
  for (auto it = panels.begin(); it != panels.end();)
    it = it->series.front().x.empty() && it->series.size() == 1 ? panels.erase(it) : it + 1;
  if (panels.empty()) return std::nullopt;
  report::PlotSpec spec;
  spec.title = "the worst-case figures against " + column;
  spec.xlabel = column;
  spec.height_px = 300 * static_cast<int>(panels.size()) + 100;
  return report::stacked_script(spec, panels, png);
}

std::optional<report::PlotScript> sobol_script(const std::string& figure, const json& sobol,
                                               const std::string& png) {
  std::vector<std::string> names;
  report::BarSeries first{"first order", {}, {}, {}}, total{"total", {}, {}, {}};
  for (const json& p : sobol["parameters"]) {
    names.push_back(p["path"].get<std::string>());
    first.value.push_back(json_or_nan(p["first"]["estimate"]));
    first.lo.push_back(json_or_nan(p["first"]["lo"]));
    first.hi.push_back(json_or_nan(p["first"]["hi"]));
    total.value.push_back(json_or_nan(p["total"]["estimate"]));
    total.lo.push_back(json_or_nan(p["total"]["lo"]));
    total.hi.push_back(json_or_nan(p["total"]["hi"]));
  }
  // Nothing to draw where the figure does not vary (an indicator with no unstable machine).
  if (names.empty() || std::none_of(first.value.begin(), first.value.end(),
                                    [](double v) { return std::isfinite(v); }))
    return std::nullopt;
  report::PlotSpec spec;
  spec.title = figure + ": Sobol indices with their 95 % bootstrap intervals (" +
               std::to_string(sobol["base_rows"].get<long>()) + " base rows)";
  spec.ylabel = "share of the variance";
  return report::interval_bars_script(spec, names, {first, total}, png);
}

report::PlotScript p_unstable_script(const json& convergence, const std::string& png) {
  report::Series estimate{"estimate", {}, {}, "linespoints lw 2 pt 7 lc rgb '#1f4e79'"};
  report::Series lo{"Clopper-Pearson 95 % interval", {}, {}, "lines lw 2 dt 2 lc rgb '#d62728'"};
  report::Series hi{"", {}, {}, "lines lw 2 dt 2 lc rgb '#d62728'"};
  for (const json& c : convergence) {
    const auto n = static_cast<double>(c["n"].get<long>());
    estimate.x.push_back(n), lo.x.push_back(n), hi.x.push_back(n);
    estimate.y.push_back(json_or_nan(c["estimate"]));
    lo.y.push_back(json_or_nan(c["lo"]));
    hi.y.push_back(json_or_nan(c["hi"]));
  }
  report::PlotSpec spec;
  spec.title = "P(unstable) over the first n evaluations";
  spec.xlabel = "n (evaluations)";
  spec.ylabel = "P(unstable)";
  spec.logx = true;
  return report::lines_script(spec, {estimate, lo, hi}, png);
}

// The pictures that may be drawn, each with the builder of its script, in the order report.md
// shows them. A builder runs when its picture's turn comes (in one of draw_plots's threads), so
// that a large campaign's scripts (millions of points as text) are not all in memory at once.
class PictureList {
 public:
  explicit PictureList(std::string out_dir) : out_dir_(std::move(out_dir)) {}
  std::string path(const std::string& file) const { return out_dir_ + "/" + file; }
  void add(Picture picture, report::PlotBuilder build) {
    pictures_.push_back(std::move(picture));
    builders_.push_back(std::move(build));
  }
  // Every picture drawn, one gnuplot process per core; the pictures drawn.
  std::vector<Picture> draw() const {
    const std::vector<bool> drawn = report::draw_plots(
        builders_, static_cast<int>(std::max(1U, std::thread::hardware_concurrency())));
    std::vector<Picture> out;
    for (std::size_t k = 0; k < pictures_.size(); ++k)
      if (drawn[k]) out.push_back(pictures_[k]);
    return out;
  }

 private:
  std::string out_dir_;
  std::vector<Picture> pictures_;
  std::vector<report::PlotBuilder> builders_;
};

}  // namespace

std::vector<Picture> draw_campaign_pictures(const json& plan, const SampleTable& table,
                                            const MachineTable& machines, const json& summary,
                                            const std::string& out_dir) {
  // Statistics over the independent machines, as the summary's (a Saltelli design's A and B
  // rows); the scatter against a parameter shows every evaluation.
  const std::vector<SampleStatus>& status = machines.status;
  const std::vector<FigureColumn>& figures = machines.figures();
  PictureList list(out_dir);
  list.add({"p_unstable.png", "P(unstable) and its interval against n"}, [&] {
    return p_unstable_script(summary["p_unstable_convergence"], list.path("p_unstable.png"));
  });
  for (const FigureColumn& f : figures) {
    const std::string file = "ecdf_" + file_stem(f.name) + ".png";
    list.add({file, "ECDF of " + f.name + " with its quantile intervals"},
             [&, file]() -> std::optional<report::PlotScript> {
               const auto xs = population_values(f, status, static_cast<long>(status.size()));
               if (xs.empty()) return std::nullopt;
               return ecdf_script(f.name, xs, to_string(f.population),
                                  summary["figures"][f.name]["quantiles"], list.path(file));
             });
  }
  for (int r = 1; r <= kHistogramRanks; ++r) {
    const std::string name = "natural_frequency_" + std::to_string(r) + "_hz";
    const auto it = std::find_if(figures.begin(), figures.end(),
                                 [&](const FigureColumn& f) { return f.name == name; });
    if (it == figures.end()) break;
    const std::string file = "histogram_" + name + ".png";
    list.add({file, "histogram of " + name},
             [&, it, name, file]() -> std::optional<report::PlotScript> {
               const auto xs = population_values(*it, status, static_cast<long>(status.size()));
               if (xs.empty()) return std::nullopt;
               return histogram_script(name, xs, list.path(file));
             });
  }
  list.add({"sigma_envelope.png", "closed-loop sigma envelope against the nominal"}, [&] {
    return sigma_envelope_script(plan, table.sigma, list.path("sigma_envelope.png"));
  });
  if (plan.contains("columns"))
    for (std::size_t c = 0; c < plan["columns"].size(); ++c) {
      const std::string column = plan["columns"][c].get<std::string>(),
                        file = "scatter_" + file_stem(column) + ".png";
      list.add({file, "the worst figures against " + column},
               [&, column, c, file] { return scatter_script(column, c, table, list.path(file)); });
    }
  if (summary.contains("sobol"))
    for (const auto& [figure, sobol] : summary["sobol"].items()) {
      const std::string file = "sobol_" + file_stem(figure) + ".png";
      list.add({file, "Sobol indices of " + figure}, [&, figure = figure, file] {
        return sobol_script(figure, summary["sobol"][figure], list.path(file));
      });
    }
  return list.draw();
}

}  // namespace flexloop::campaign
