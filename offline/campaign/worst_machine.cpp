// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/worst_machine.hpp"

#include <nlopt.h>

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/campaign/designs.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/campaign/sample_table.hpp"
#include "offline/campaign/worst_samples.hpp"

namespace flexloop::campaign {

namespace {

using nlohmann::json;
constexpr double kUnbounded = std::numeric_limits<double>::infinity();
/// A non-uniform column's box: its quantiles [kBoxTail, 1 - kBoxTail].
constexpr double kBoxTail = 1e-6;

bool uniform_column(const PlannedColumn& c) {
  return std::all_of(c.distributions.begin(), c.distributions.end(),
                     [](const Distribution& d) { return d.kind == DistributionKind::kUniform; });
}

// Every machine evaluated in the search, the worst kept: the figures at a point of the box.
class WorstSearch {
 public:
  WorstSearch(const PlanSamples& samples, WorstMachine& w, long budget, const WorstProgress& p)
      : samples_(samples), w_(w), budget_(budget), progress_(p) {}

  // The badness of the machine at unit point u (clamped into the box).
  double evaluate(std::vector<double> u) {
    for (std::size_t c = 0; c < u.size(); ++c)
      u[c] = std::clamp(u[c], w_.box_low[c], w_.box_high[c]);
    const ParameterValues values = values_at(samples_.columns(), u);
    json figures = samples_.figures_at(values);
    const double b = badness(figures, w_.figure);
    ++w_.evaluations;
    if (w_.evaluations == 1 || b > w_.badness) {
      w_.badness = b;
      w_.figures = std::move(figures);
      w_.values = values;
      w_.unit_point = u;
    }
    if (progress_) progress_(w_.evaluations, budget_);
    return b;
  }
  // Nothing is worse than what was found: an unstable loop for a figure it does not have.
  bool ended() const { return w_.badness == kUnbounded; }

 private:
  const PlanSamples& samples_;
  WorstMachine& w_;
  long budget_;
  WorstProgress progress_;
};

// Sampled machine i's unit point: the plan's Latin hypercube.
std::vector<double> sample_point(const json& plan, int d, long i) {
  return unit_point(DesignKind::kLatinHypercube, plan.at("n").get<long>(), d,
                    plan.at("seed").get<std::uint64_t>(), i);
}

// The n sampled machines' badness, in sample order.
std::vector<double> sample_machines(WorstSearch& search, const json& plan, int d) {
  std::vector<double> out;
  for (long i = 0; i < plan.at("n").get<long>(); ++i)
    out.push_back(search.evaluate(sample_point(plan, d, i)));
  return out;
}

struct LocalSearch {
  WorstSearch* search;
  const WorstMachine* w;
  nlopt_opt opt = nullptr;
  long evaluations = 0;
};

/// What the objective returns for a machine that cannot be the worst.
constexpr double kNotWorst = 1e30;

// NLopt's objective: minimise -badness over x in [0, 1]^d, x the position inside the box.
double negative_badness(unsigned d, const double* x, double*, void* data) {
  auto& s = *static_cast<LocalSearch*>(data);
  std::vector<double> u(d);
  for (unsigned c = 0; c < d; ++c)
    u[c] = s.w->box_low[c] + x[c] * (s.w->box_high[c] - s.w->box_low[c]);
  ++s.evaluations;
  const double b = s.search->evaluate(u);
  if (s.search->ended()) {
    nlopt_force_stop(s.opt);  // nothing is worse than what was found
    return 0;
  }
  // A machine without the figure (refused, an unbounded margin) is never the worst: a large
  // finite value, as BOBYQA's quadratic model needs one.
  return std::isfinite(b) ? -b : kNotWorst;
}

const char* stop_reason(nlopt_result r) {
  switch (r) {
    case NLOPT_MAXEVAL_REACHED:
      return "its share of the evaluations used";
    case NLOPT_XTOL_REACHED:
      return "converged (the point moved less than 1e-6 of the box)";
    case NLOPT_FTOL_REACHED:
      return "converged (the figure changed less than 1e-9 relative)";
    case NLOPT_FORCED_STOP:
      return "stopped: an unstable loop, worse than any number";
    default:
      return r > 0 ? "converged" : "NLopt failed";
  }
}

// One local search from sampled machine `from`, at most `budget` evaluations.
WorstStart search_from(WorstSearch& search, const WorstMachine& w, long from, double from_badness,
                       const std::vector<double>& u0, long budget) {
  const auto d = static_cast<unsigned>(u0.size());
  std::vector<double> x(d), zero(d, 0.0), one(d, 1.0);
  for (unsigned c = 0; c < d; ++c)
    x[c] = (std::clamp(u0[c], w.box_low[c], w.box_high[c]) - w.box_low[c]) /
           (w.box_high[c] - w.box_low[c]);
  nlopt_opt opt = nlopt_create(NLOPT_LN_BOBYQA, d);
  LocalSearch state{&search, &w, opt};
  nlopt_set_lower_bounds(opt, zero.data());
  nlopt_set_upper_bounds(opt, one.data());
  nlopt_set_min_objective(opt, negative_badness, &state);
  nlopt_set_maxeval(opt, static_cast<int>(budget));
  nlopt_set_xtol_rel(opt, 1e-6);
  nlopt_set_ftol_rel(opt, 1e-9);
  nlopt_set_initial_step1(opt, 0.1);  // a tenth of the box
  double f = 0;
  const nlopt_result r = nlopt_optimize(opt, x.data(), &f);
  nlopt_destroy(opt);
  return {from, from_badness, search.ended() ? kUnbounded : (std::isfinite(f) ? -f : -kUnbounded),
          state.evaluations, search.ended() ? stop_reason(NLOPT_FORCED_STOP) : stop_reason(r)};
}

// The box of each column in u (the file's header).
void set_box(const std::vector<PlannedColumn>& columns, double sigmas, WorstMachine& w) {
  const double tail = sigmas > 0 ? boost::math::cdf(boost::math::normal(), -sigmas) : kBoxTail;
  for (const PlannedColumn& c : columns) {
    const bool uniform = uniform_column(c);
    w.box_low.push_back(uniform ? 0.0 : tail);
    w.box_high.push_back(uniform ? 1.0 : 1 - tail);
    w.columns.push_back(c.name);
  }
}

void check_request(const WorstRequest& r) {
  if (!(r.sigmas >= 0 && std::isfinite(r.sigmas)))
    throw common::InputError("--sigmas",
                             "the box's half-width must be a number of standard "
                             "deviations above 0");
  if (r.starts < 1) throw common::InputError("--starts", "at least one local search");
  if (r.evaluations < 0)
    throw common::InputError("--evaluations", "the local searches' budget must be >= 0");
}

}  // namespace

WorstFigure worst_figure_from_name(const std::string& name,
                                   const std::vector<std::string>& performance_channels) {
  if (name == "spectral_radius" || name == "largest_inner_radius" || name == "peak_sigma")
    return {name, "", false};
  if (name == "disk_margin_db") return {name, "", true};
  std::string channel;
  if (name == "rms" && performance_channels.size() == 1) channel = performance_channels.front();
  if (name.rfind("rms.", 0) == 0) channel = name.substr(4);
  if (!channel.empty() && std::find(performance_channels.begin(), performance_channels.end(),
                                    channel) != performance_channels.end())
    return {"rms." + channel, channel, false};
  std::string choices = "spectral_radius, largest_inner_radius, disk_margin_db, peak_sigma";
  for (const std::string& c : performance_channels) choices += ", rms." + c;
  throw common::InputError("--figure", "'" + name + "' is not one of " + choices);
}

double badness(const json& figures, const WorstFigure& f) {
  const std::string status = figures.value("status", std::string());
  const bool unstable = status == "unstable", marginal = status.rfind("marginal", 0) == 0;
  if (!unstable && !marginal && status != "stable") return -kUnbounded;  // refused, failed
  if (f.name == "spectral_radius") return figure_value(figures.value("spectral_radius", json()));
  if (unstable) return kUnbounded;  // no margin, sigma or RMS: worse than any
  if (!f.channel.empty()) {
    const json rms = figures.value("rms", json());
    if (!rms.is_object())
      return marginal ? kUnbounded : -kUnbounded;  // no stationary state: unbounded
    return figure_value(rms.value(f.channel, json()));
  }
  const double v = figure_value(figures.value(f.name, json()));
  if (std::isnan(v)) return -kUnbounded;
  return f.smaller_is_worse ? -v : v;
}

namespace {

// The local searches from the worst sampled machines (a machine without the figure never starts
// one), the budget shared between them, until it is used or nothing can be worse.
void search_from_worst_samples(WorstSearch& search, WorstMachine& w, const json& plan,
                               const std::vector<double>& sampled, const WorstRequest& r) {
  std::vector<long> order(sampled.size());
  std::iota(order.begin(), order.end(), 0L);
  std::stable_sort(order.begin(), order.end(),
                   [&](long a, long b) { return sampled[a] > sampled[b]; });
  long starts = 0;
  for (long i : order)
    starts += starts < r.starts && sampled[static_cast<std::size_t>(i)] > -kUnbounded;
  const int d = static_cast<int>(w.columns.size());
  long left = r.evaluations;
  for (long k = 0; k < starts && left > 0 && !search.ended() && d > 0; ++k) {
    const long i = order[static_cast<std::size_t>(k)];
    const long budget = left / (starts - k);
    w.starts.push_back(search_from(search, w, i, sampled[static_cast<std::size_t>(i)],
                                   sample_point(plan, d, i), budget));
    left -= w.starts.back().evaluations;
  }
}

}  // namespace

WorstMachine find_worst_machine(const WorstRequest& r, const WorstProgress& progress) {
  check_request(r);
  PlanRequest pr = r.plan;
  pr.design = "lhs";
  const json plan = make_plan(pr);
  const PlanSamples samples(plan);
  WorstMachine w;
  w.plan = plan;
  w.figure =
      worst_figure_from_name(r.figure, samples.documents().nominal_machine().scene.performance);
  set_box(samples.columns(), r.sigmas, w);
  WorstSearch search(samples, w, plan.at("n").get<long>() + r.evaluations, progress);
  const std::vector<double> sampled =
      sample_machines(search, plan, static_cast<int>(w.columns.size()));
  w.sampled = static_cast<long>(sampled.size());
  w.worst_sampled_badness = w.badness;
  search_from_worst_samples(search, w, plan, sampled, r);
  return w;
}

namespace {

// A figure's value as worst.json writes it: the number, "+inf"/"-inf", null when there is none.
json figure_of(const WorstMachine& w) {
  if (!w.figure.channel.empty()) {
    const json rms = w.figures.value("rms", json());
    return rms.is_object() ? rms.value(w.figure.channel, json()) : json();
  }
  return w.figures.value(w.figure.name, json());
}

// The figure a badness stands for, a margin's sign turned back: an unstable loop's margin reads
// -inf (worse than any), its RMS or sigma +inf.
double figure_of_badness(double badness, const WorstFigure& f) {
  return f.smaller_is_worse ? -badness : badness;
}

json starts_json(const WorstMachine& w) {
  json out = json::array();
  for (const WorstStart& s : w.starts)
    out.push_back(
        {{"sample", s.sample},
         {"start_value", number_or_infinity(figure_of_badness(s.start_badness, w.figure))},
         {"end_value", number_or_infinity(figure_of_badness(s.end_badness, w.figure))},
         {"evaluations", s.evaluations},
         {"stopped", s.stopped}});
  return out;
}

}  // namespace

json worst_machine_json(const WorstMachine& w) {
  json parameters = json::object(), box = json::array();
  for (const auto& [path, value] : w.values) parameters[path] = value;
  for (std::size_t c = 0; c < w.columns.size(); ++c)
    box.push_back({{"column", w.columns[c]}, {"u_low", w.box_low[c]}, {"u_high", w.box_high[c]}});
  return {{"format", "flexloop-worst-machine"},
          {"version", 1},
          {"figure", w.figure.name},
          {"direction", w.figure.smaller_is_worse ? "smallest" : "largest"},
          {"value", figure_of(w)},
          {"status", w.figures.value("status", std::string())},
          {"badness", number_or_infinity(w.badness)},
          {"worst_sampled_badness", number_or_infinity(w.worst_sampled_badness)},
          {"worst_sampled_value",
           number_or_infinity(figure_of_badness(w.worst_sampled_badness, w.figure))},
          {"parameters", parameters},
          {"unit_point", w.unit_point},
          {"box", box},
          {"evaluations", w.evaluations},
          {"sampled", {{"n", w.sampled}, {"design", "lhs"}, {"seed", w.plan.at("seed")}}},
          {"optimiser", "NLopt LN_BOBYQA (Powell), bounded, derivative-free"},
          {"starts", starts_json(w)},
          {"scene", w.plan.at("scene")},
          {"plan_id", w.plan.at("plan_id")},
          {"figures", w.figures}};
}

std::string write_worst_machine(const WorstMachine& w, const std::string& out_dir) {
  const std::filesystem::path dir(out_dir);
  std::filesystem::create_directories(dir);
  const MachineDocuments docs(w.plan.at("scene").get<std::string>());
  const SampleScene texts = machine_scene(docs, w.plan, w.values,
                                          "the worst machine for " + w.figure.name + " (status " +
                                              w.figures.value("status", std::string("?")) + ")",
                                          "_worst", "worst_model.toml");
  common::write_text_atomically(dir / "worst_model.toml", texts.model_text);
  common::write_text_atomically(dir / "worst.toml", texts.scene_text);
  common::write_text_atomically(dir / "worst.json", worst_machine_json(w).dump(2) + "\n");
  return (dir / "worst.toml").string();
}

}  // namespace flexloop::campaign
