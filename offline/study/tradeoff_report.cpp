// SPDX-License-Identifier: BSD-3-Clause
#include "offline/study/tradeoff_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "common/atomic_file.hpp"
#include "offline/report/plot.hpp"

namespace flexloop::study {
namespace {

std::string number(double x, const char* format = "%.3g") {
  if (std::isnan(x)) return "-";
  if (std::isinf(x)) return "inf";
  char b[32];
  std::snprintf(b, sizeof b, format, x);
  return b;
}

// Row indices of the measured rows by ns per step.
std::vector<std::size_t> measured_by_cost(const TradeoffResult& r) {
  std::vector<std::size_t> v;
  for (std::size_t k = 0; k < r.rows.size(); ++k)
    if (r.rows[k].skipped.empty()) v.push_back(k);
  std::stable_sort(v.begin(), v.end(), [&](auto a, auto b) {
    return cost_of(r.rows[a], r.cost) < cost_of(r.rows[b], r.cost);
  });
  return v;
}

// Above round-off: a double integrator's computed poles sit within ~sqrt(eps) of z = 1.
const char* cost_name(Cost c) {
  return c == Cost::kStep ? "ns/step" : "share of the period";
}

bool unstable(const Measurement& m) {
  return m.closed_loop_radius > 1 + 1e-6;
}

long default_row(const TradeoffResult& r) {
  const Configuration& d = r.default_config;
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const Configuration& c = r.rows[k].config;
    if (r.rows[k].skipped.empty() && c.method == d.method && c.prewarp == d.prewarp &&
        c.rate_hz == d.rate_hz && c.form == d.form && c.scalar == d.scalar &&
        c.reduction == d.reduction)
      return static_cast<long>(k);
  }
  return -1;
}

}  // namespace

void print_table(std::ostream& out, const TradeoffResult& r) {
  const std::vector<std::size_t> front = pareto_front(r);
  char line[256];
  std::snprintf(line, sizeof line,
                "  %-15s %8s %-6s %-6s %-9s %5s %9s %9s %9s %10s %9s %9s %8s %-8s\n", "method",
                "rate Hz", "form", "scalar", "reduction", "order", "H-inf err", "DC err",
                "step err", "loop err", "loop RMS", "ns/step", "period", "kernel");
  out << line;
  std::size_t skipped = 0;
  for (const auto& m : r.rows) skipped += !m.skipped.empty();
  for (const std::size_t k : measured_by_cost(r)) {
    const Measurement& m = r.rows[k];
    const Configuration& c = m.config;
    const bool on_front = std::find(front.begin(), front.end(), k) != front.end();
    std::snprintf(line, sizeof line,
                  "%c %-15s %8g %-6s %-6s %-9s %5d %9s %9s %9s %9s%c %9s %9s %7s%% %-8s\n",
                  on_front ? '*' : ' ', c.method_name().c_str(), c.rate_hz,
                  artefact::to_string(c.form).c_str(), to_string(c.scalar).c_str(),
                  to_string(c.reduction).c_str(), c.order, number(m.hinf_error).c_str(),
                  number(m.dc_error).c_str(), number(m.step_error).c_str(),
                  number(m.closed_loop_error).c_str(), unstable(m) ? '!' : ' ',
                  number(m.closed_loop_rms_error).c_str(), number(m.ns_per_step, "%.1f").c_str(),
                  number(100 * m.period_share, "%.2f").c_str(), m.kernel.c_str());
    out << line;
  }
  out << "* on the Pareto front of (" << cost_name(r.cost)
      << ", H-inf error); ! the sampled loop is unstable "
         "(spectral radius > 1 + 1e-6). Errors are relative (see --help); band "
      << number(r.band_low_hz) << " .. " << number(r.band_hz) << " Hz (up to Nyquist)";
  if (skipped > 0) out << "; " << skipped << " configurations skipped (reasons in the CSV/JSON)";
  out << "\n";
}

std::string csv_header() {
  return "method,rate_hz,form,scalar,reduction,order,hinf_error,dc_error,step_error,"
         "closed_loop_error,closed_loop_rms_error,ns_per_step,ns_min,ns_max,period_share,"
         "reduction_bound,kernel,closed_loop_radius,pareto,skipped";
}

void write_csv(const std::string& path, const TradeoffResult& r) {
  const std::vector<std::size_t> front = pareto_front(r);
  std::ostringstream s;
  s.precision(6);
  s << csv_header() << "\n";
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const Measurement& m = r.rows[k];
    const Configuration& c = m.config;
    std::string why = m.skipped;
    std::replace(why.begin(), why.end(), '"', '\'');
    std::replace(why.begin(), why.end(), '\n', ' ');
    s << c.method_name() << "," << c.rate_hz << "," << artefact::to_string(c.form) << ","
      << to_string(c.scalar) << "," << to_string(c.reduction) << "," << c.order << ","
      << m.hinf_error << "," << m.dc_error << "," << m.step_error << "," << m.closed_loop_error
      << "," << m.closed_loop_rms_error << "," << m.ns_per_step << "," << m.ns_min << ","
      << m.ns_max << "," << m.period_share << "," << m.reduction_bound << "," << m.kernel << ","
      << m.closed_loop_radius << ","
      << (std::find(front.begin(), front.end(), k) != front.end() ? 1 : 0) << ",\"" << why
      << "\"\n";
  }
  common::write_text_atomically(path, s.str());
}

nlohmann::json to_json(const TradeoffResult& r) {
  const auto finite = [](double x) -> nlohmann::json {
    if (std::isfinite(x)) return x;
    return nullptr;
  };
  const auto config = [](const Configuration& c) {
    return nlohmann::json{{"method", c.method_name()},           {"rate_hz", c.rate_hz},
                          {"form", artefact::to_string(c.form)}, {"scalar", to_string(c.scalar)},
                          {"reduction", to_string(c.reduction)}, {"order", c.order}};
  };
  nlohmann::json j{{"full_order", r.full_order},
                   {"band_hz", {r.band_low_hz, r.band_hz}},
                   {"prewarp_hz", r.prewarp_hz},
                   {"default", config(r.default_config)},
                   {"rows", nlohmann::json::array()}};
  const std::vector<std::size_t> front = pareto_front(r);
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const Measurement& m = r.rows[k];
    nlohmann::json row = config(m.config);
    if (!m.skipped.empty()) {
      row["skipped"] = m.skipped;
    } else {
      row["hinf_error"] = finite(m.hinf_error);
      row["dc_error"] = finite(m.dc_error);
      row["step_error"] = finite(m.step_error);
      row["closed_loop_error"] = finite(m.closed_loop_error);
      row["closed_loop_rms_error"] = finite(m.closed_loop_rms_error);
      row["ns_per_step"] = {
          {"median", finite(m.ns_per_step)}, {"min", finite(m.ns_min)}, {"max", finite(m.ns_max)}};
      row["period_share"] = finite(m.period_share);
      row["kernel"] = m.kernel;
      row["closed_loop_radius"] = finite(m.closed_loop_radius);
      row["pareto"] = std::find(front.begin(), front.end(), k) != front.end();
    }
    row["reduction_bound"] = finite(m.reduction_bound);
    j["rows"].push_back(row);
  }
  return j;
}

namespace {

// The picture's x value of a row: ns per step, or % of the period.
double picture_cost(const Measurement& m, Cost cost) {
  return cost == Cost::kStep ? m.ns_per_step : 100 * m.period_share;
}

}  // namespace

AxisRange cost_axis(const std::vector<double>& costs) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (const double c : costs)
    if (std::isfinite(c) && c > 0) lo = std::min(lo, c), hi = std::max(hi, c);
  if (hi == 0) return {};  // nothing measured: gnuplot's own axis
  if (hi <= lo * (1 + 1e-9)) return {lo * 0.9, hi * 1.1, false};
  if (hi > 10 * lo) {
    const double margin = std::pow(hi / lo, kCostAxisMargin);
    return {lo / margin, hi * margin, true};
  }
  const double margin = kCostAxisMargin * (hi - lo);
  return {std::max(0.0, lo - margin), hi + margin, false};
}

AxisRange front_cost_axis(const TradeoffResult& r) {
  std::vector<double> costs;
  for (const Measurement& m : r.rows)
    if (m.skipped.empty()) costs.push_back(picture_cost(m, r.cost));
  return cost_axis(costs);
}

void write_front_png(const std::string& path, const TradeoffResult& r, const std::string& title) {
  const auto x_of = [&](const Measurement& m) { return picture_cost(m, r.cost); };
  report::Series all{"every configuration", {}, {}, "points pt 6 ps 1 lc rgb '#999999'"};
  for (const Measurement& m : r.rows)
    if (m.skipped.empty()) {
      all.x.push_back(x_of(m));
      all.y.push_back(m.hinf_error);
    }
  report::Series line{"Pareto front", {}, {}, "lines lw 2 lc rgb '#202020'"};
  std::vector<report::Series> series{all};
  int n = 0;
  for (const std::size_t k : pareto_front(r)) {
    const Measurement& m = r.rows[k];
    line.x.push_back(x_of(m));
    line.y.push_back(m.hinf_error);
    series.push_back({std::to_string(++n) + ": " + m.config.label(),
                      {x_of(m)},
                      {m.hinf_error},
                      "points pt 7 ps 2"});
  }
  series.insert(series.begin() + 1, line);
  const AxisRange axis = front_cost_axis(r);
  report::plot_lines({.title = title,
                      .xlabel = r.cost == Cost::kStep ? "closed-loop step [ns]"
                                                      : "closed-loop step [% of the period]",
                      .ylabel = "relative H-inf error in the band",
                      .logx = axis.log,
                      .logy = true,
                      .width_px = 1200,
                      .height_px = 750,
                      .x_min = axis.min,
                      .x_max = axis.max},
                     series, path);
}

std::string budget_answer(const TradeoffResult& r, double budget) {
  std::ostringstream s;
  const long best = cheapest_within(r, budget);
  if (best < 0) {
    s << "no configuration is within an H-inf error of " << number(budget);
    return s.str();
  }
  const Measurement& b = r.rows[static_cast<std::size_t>(best)];
  s << "cheapest (" << cost_name(r.cost) << ") within an H-inf error of " << number(budget) << ": "
    << b.config.label() << ", " << number(b.ns_per_step, "%.1f") << " ns/step ("
    << number(100 * b.period_share, "%.2f") << " % of its period), error " << number(b.hinf_error);
  const long d = default_row(r);
  if (d < 0) {
    s << "; the default (" << r.default_config.label() << ") was not in the sweep";
    return s.str();
  }
  const Measurement& m = r.rows[static_cast<std::size_t>(d)];
  s << "; the default (" << m.config.label() << ") takes " << number(m.ns_per_step, "%.1f")
    << " ns/step (" << number(100 * m.period_share, "%.2f") << " % of its period) at error "
    << number(m.hinf_error) << ": " << number(100 * (1 - b.ns_per_step / m.ns_per_step), "%.0f")
    << " % less time per step";
  return s.str();
}

}  // namespace flexloop::study
