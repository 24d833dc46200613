// SPDX-License-Identifier: BSD-3-Clause
#include "offline/study/tradeoff.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <sstream>

#include "common/input_error.hpp"
#include "controller/runtime/controller_from_artefact.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/study/study_loop.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/model_reduction.hpp"
#include "plant/runtime/effects/floor_generator.hpp"
#include "plant/runtime/effects/white_floor.hpp"
#include "plant/runtime/plant_from_artefact.hpp"

namespace flexloop::study {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Response = std::vector<Eigen::MatrixXcd>;
namespace lti = plant::lti;
namespace fx = plant::runtime::effects;

// The plant of one row: the full model or a reduced one.
struct Variant {
  std::string reduction;
  int order = 0;
  lti::StateSpace sys;
  double bound = NAN;
  std::string error;  // the reduction failed: why
};

std::vector<int> default_orders(int n) {
  std::vector<int> v;
  for (const int k : {3 * n / 4, n / 2, n / 4}) {
    const int even = std::max(2, k - k % 2);
    if (even < n && std::find(v.begin(), v.end(), even) == v.end()) v.push_back(even);
  }
  return v;
}

// band: the study's band, where modal truncation judges the modes' contributions.
std::vector<Variant> variants(const scene::ScenePlant& p, const TradeoffOptions& o,
                              std::array<double, 2> band) {
  const int n = static_cast<int>(p.plant.nx());
  std::vector<Variant> v{{"full", n, p.plant, NAN, ""}};
  const std::vector<int> orders = o.orders.empty() ? default_orders(n) : o.orders;
  for (const std::string& r : o.reductions)
    for (const int order : orders) {
      Variant x{r, order, {}, NAN, ""};
      try {
        const lti::ReducedModel m =
            r == "balanced" ? lti::balanced_truncation(p.plant, order)
                            : lti::modal_truncation(p.plant, {.order = order,
                                                              .dc_correction = r == "modal-dc",
                                                              .band_low_hz = band[0],
                                                              .band_hz = band[1]});
        x.sys = m.sys;
        x.order = static_cast<int>(m.sys.nx());
        x.bound = m.error_bound;
      } catch (const std::exception& e) {
        x.error = e.what();
      }
      v.push_back(std::move(x));
    }
  return v;
}

lti::DiscretisationMethod method_of(const std::string& m) {
  return lti::parse_discretisation_method(m == "tustin-prewarp" ? "tustin" : m);
}

constexpr std::pair<Reduction, const char*> kReductionNames[] = {
    {Reduction::kFull, "full"},
    {Reduction::kModal, "modal"},
    {Reduction::kModalDc, "modal-dc"},
    {Reduction::kBalanced, "balanced"}};

// The reduction a --reductions name (or "full") stands for; the names were checked.
Reduction reduction_of(const std::string& name) {
  for (const auto& [r, text] : kReductionNames)
    if (name == text) return r;
  throw std::invalid_argument("unknown reduction '" + name + "'");
}

// The floor the scene's loop sees at the artefact's rate, from rest, `steps` samples.
MatrixXd floor_samples(const artefact::LoopArtefact& a, long steps) {
  const Index nw = a.disturbances();
  MatrixXd w(nw, steps);
  auto fill = [&](auto floor) {
    for (long k = 0; k < steps; ++k) w.col(k) = floor.step();
  };
  if (a.floor.spectrum == artefact::FloorSpectrum::kWhite)
    fill(fx::WhiteFloor<double, Eigen::Dynamic>::from_parameters(a.floor.rms_mps2, a.floor.seed,
                                                                 nw));
  else
    fill(fx::FloorGenerator<double, Eigen::Dynamic, artefact::kFloorFilterOrder>::from_parameters(
        a.floor_filter.A, a.floor_filter.B, a.floor_filter.C, a.floor_filter.D, a.floor.seed,
        fx::FloorStart::kAtRest, nw));
  return w;
}

// The plant as the runtime stores it (Ad - I or Λ - I, B, C, D in `Scalar`), as a discrete
// system in double for its frequency response.
template <typename Scalar>
lti::DiscreteStateSpace stored_plant(const artefact::LoopArtefact& a) {
  const auto& d = a.plant;
  const bool modal = d.form == artefact::PlantForm::kModal;
  const auto round = [](const MatrixXd& m) -> MatrixXd {
    return m.cast<Scalar>().template cast<double>();
  };
  const MatrixXd step =
      modal ? d.modal.Lambda_minus_I : MatrixXd(d.A - MatrixXd::Identity(d.A.rows(), d.A.cols()));
  lti::DiscreteStateSpace s;
  s.sys.A = MatrixXd::Identity(step.rows(), step.cols()) + round(step);
  s.sys.B = round(modal ? d.modal.B : d.B);
  s.sys.C = round(modal ? d.modal.C : d.C);
  s.sys.D = round(modal ? d.modal.D : d.D);
  for (Index k = 0; k < s.sys.A.rows(); ++k) s.sys.states.push_back("x" + std::to_string(k));
  s.sys.inputs = a.names(a.channels.disturbances);
  for (const auto& c : a.channels.actuators) s.sys.inputs.push_back(c.name);
  s.sys.outputs = a.names(a.channels.performance);
  for (const auto& c : a.channels.sensors) s.sys.outputs.push_back(c.name);
  s.dt = a.dt();
  return s;
}

// A pair whose peak is below this share of the largest peak among the pairs with its units (a
// coupling that symmetry makes nearly zero) is judged against that share, not against itself.
constexpr double kNegligiblePair = 1e-3;

// What each pair's error is relative to: its peak, or kNegligiblePair x the largest peak of the
// pairs with the same output and input units, whichever is larger.
MatrixXd error_scale(const MatrixXd& peak, const lti::StateSpace& sys) {
  std::vector<std::string> out, in;
  for (const auto& c : sys.outputs) out.push_back(scene::channel_unit(c));
  for (const auto& c : sys.inputs) in.push_back(scene::channel_unit(c));
  MatrixXd scale = peak;
  for (Index i = 0; i < peak.rows(); ++i)
    for (Index j = 0; j < peak.cols(); ++j) {
      double block = 0;
      for (Index k = 0; k < peak.rows(); ++k)
        for (Index l = 0; l < peak.cols(); ++l)
          if (out[k] == out[i] && in[l] == in[j]) block = std::max(block, peak(k, l));
      scale(i, j) = std::max(peak(i, j), kNegligiblePair * block);
    }
  return scale;
}

// Worst pair of max_f |H_ij - G_ij| / scale_ij.
double relative_error(const Response& h, const Response& g, const MatrixXd& scale) {
  double worst = 0;
  for (std::size_t k = 0; k < h.size(); ++k)
    for (Index i = 0; i < scale.rows(); ++i)
      for (Index j = 0; j < scale.cols(); ++j)
        if (scale(i, j) > 0)
          worst = std::max(worst, std::abs(h[k](i, j) - g[k](i, j)) / scale(i, j));
  return worst;
}

// Worst row of max_k |y - y_ref| / max_k |y_ref| (rms = false) or RMS(y - y_ref) / RMS(y_ref).
double worst_row_error(const MatrixXd& y, const MatrixXd& ref, bool rms) {
  double worst = 0;
  for (Index i = 0; i < ref.rows(); ++i) {
    const double scale = rms ? ref.row(i).norm() : ref.row(i).cwiseAbs().maxCoeff();
    const double diff =
        rms ? (y.row(i) - ref.row(i)).norm() : (y.row(i) - ref.row(i)).cwiseAbs().maxCoeff();
    if (scale > 0)
      worst = std::max(worst, diff / scale);
    else if (diff > 0)
      worst = INFINITY;
  }
  return y.allFinite() ? worst : INFINITY;  // a run that went non-finite is not 'close'
}

double worst_rms_ratio(const MatrixXd& z, const MatrixXd& ref) {
  double worst = 0;
  for (Index i = 0; i < ref.rows(); ++i)
    if (ref.row(i).norm() > 0)
      worst = std::max(worst, std::abs(z.row(i).norm() / ref.row(i).norm() - 1));
  return z.allFinite() ? worst : INFINITY;
}

// f(controller): the artefact's controller (controller/runtime/controller_from_artefact.hpp), a
// zero command for a loop without one.
template <typename Scalar, class F>
decltype(auto) with_controller_or_zero(const artefact::LoopArtefact& a, F&& f) {
  if (a.controller == artefact::ControllerKind::kNone)
    return f(ZeroCommand<Scalar>{Eigen::Matrix<Scalar, Eigen::Dynamic, 1>::Zero(a.actuators())});
  // Foreign code (a controller FMU) is refused: the study times flexloop's own kernels.
  return controller::runtime::with_controller<Scalar, Eigen::Dynamic, Eigen::Dynamic>(a, f);
}

// What the runtime kernels of one configuration give: open-loop step, closed-loop z, and a timer
// that owns a copy of the loop: timed(steps) runs that many closed-loop steps (after a tenth of
// them untimed, to warm the caches) and returns ns per step.
struct KernelRuns {
  MatrixXd step, z;
  std::function<double(long)> timed;
  std::string kernel;  // "compiled" or "general"
};

template <typename Scalar>
KernelRuns kernel_runs(const artefact::LoopArtefact& a, const MatrixXd& floor, long steps) {
  KernelRuns r;
  const Index nz = a.performance(), ns = a.sensors();
  using Floor = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  const auto w = std::make_shared<const Floor>(floor.cast<Scalar>());
  // NW, NS: compiled counts, or Eigen::Dynamic.
  auto measure = [&](auto plant, auto controller, auto nw_count, auto ns_count) {
    constexpr int NW = decltype(nw_count)::value, NS = decltype(ns_count)::value;
    auto open = plant;
    r.step = unit_step<NW>(open, a.disturbances(), steps);
    auto loop_plant = plant;
    auto loop_controller = controller;
    r.z.resize(nz, steps);
    run_loop<NW, NS>(loop_plant, loop_controller, *w, nz, ns, steps, &r.z);
    r.timed = [plant, controller, w, nz, ns](long n) mutable {
      run_loop<NW, NS>(plant, controller, *w, nz, ns, std::max(n / 10, 1L), nullptr);
      const auto t0 = std::chrono::steady_clock::now();
      run_loop<NW, NS>(plant, controller, *w, nz, ns, n, nullptr);
      const auto t1 = std::chrono::steady_clock::now();
      return std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n);
    };
  };
  // The kernels `flexloop sim` would use: a compiled loop where one matches (double, the PI),
  // otherwise the general path.
  if constexpr (std::is_same_v<Scalar, double>)
    if (controller::runtime::has_compiled_kernels(a.controller))
      plant::runtime::with_compiled_loop(
          plant::runtime::loop_counts(a),
          [&](auto loop) {
            using Loop = decltype(loop);
            controller::runtime::with_controller<double, Loop::NC, Loop::NS>(
                a, [&](auto controller) {
                  measure(plant::runtime::make_compiled_plant<Loop>(a), controller,
                          std::integral_constant<int, Loop::NW>{},
                          std::integral_constant<int, Loop::NS>{});
                });
            r.kernel = "compiled";
          },
          [] {});
  if (r.kernel.empty()) {
    plant::runtime::with_general_plant<Scalar>(a, [&](auto plant) {
      with_controller_or_zero<Scalar>(a, [&](auto controller) {
        measure(plant, controller, std::integral_constant<int, Eigen::Dynamic>{},
                std::integral_constant<int, Eigen::Dynamic>{});
      });
    });
    r.kernel = "general";
  }
  return r;
}

// The continuous reference on a rate's grid, with each pair's peak.
struct Reference {
  std::vector<double> f;
  Response g;
  MatrixXd peak;        // what each pair's error is relative to (error_scale)
  Eigen::MatrixXcd dc;  // empty: a pole at the origin
};

// What the sweep walks besides the plants and the options' own lists: the plant forms and the
// rates (the scene's rate / 10, / 2, x 1, x 2 when none are given), each option checked first.
struct Sweep {
  std::vector<artefact::PlantForm> forms;
  std::vector<double> rates;
};

Sweep checked_sweep(const scene::ScenePlant& p, const TradeoffOptions& o) {
  const std::string& file = p.scene.file;
  for (const std::string& m : o.methods) try {
      (void)method_of(m);
    } catch (const std::invalid_argument&) {
      throw common::InputError(file,
                               "--methods: unknown method '" + m +
                                   "' (zoh, foh, tustin, tustin-prewarp, backward-euler, euler)");
    }
  Sweep sweep;
  for (const std::string& f : o.forms) try {
      sweep.forms.push_back(artefact::parse_plant_form(f));
    } catch (const std::invalid_argument&) {
      throw common::InputError(file, "--forms: '" + f + "' (dense, modal)");
    }
  for (const std::string& s : o.scalars)
    if (s != "double" && s != "float")
      throw common::InputError(file, "--scalars: '" + s + "' (double, float)");
  for (const std::string& r : o.reductions)
    if (r != "modal" && r != "modal-dc" && r != "balanced")
      throw common::InputError(file, "--reductions: '" + r + "' (modal, modal-dc, balanced)");
  const int n = static_cast<int>(p.plant.nx());
  for (const int k : o.orders)
    if (k < 1 || k > n)
      throw common::InputError(file, "--orders: " + std::to_string(k) + " is outside 1 .. " +
                                         std::to_string(n) + " (the full order)");
  const auto& sd = p.scene.discretisation;
  sweep.rates = o.rates_hz;
  if (sweep.rates.empty())
    sweep.rates = {sd.rate_hz / 10, sd.rate_hz / 2, sd.rate_hz, 2 * sd.rate_hz};
  for (const double r : sweep.rates)
    if (!(r > 0 && r <= scene::kMaxLoopRateHz))
      throw common::InputError(file, "--rates: each rate must be in (0, " +
                                         std::to_string(static_cast<long>(scene::kMaxLoopRateHz)) +
                                         "] Hz (the loop commands' ceiling)");
  return sweep;
}

// The result before its rows: the scene's own configuration, and the band [f_min / 10, f_hi]
// (f_hi: --band, else 2 f_max) of the natural frequencies f_min .. f_max, whose lowest is also
// tustin-prewarp's frequency.
TradeoffResult result_frame(const scene::ScenePlant& p, const TradeoffOptions& o) {
  const auto& sd = p.scene.discretisation;
  TradeoffResult result;
  result.full_order = static_cast<int>(p.plant.nx());
  result.cost = o.cost;
  result.default_config = {.method = sd.method,
                           .prewarp = sd.prewarp_hz > 0,
                           .rate_hz = sd.rate_hz,
                           .form = artefact::PlantForm::kDense,
                           .scalar = Scalar::kDouble,
                           .reduction = Reduction::kFull,
                           .order = result.full_order};
  const Eigen::VectorXd& fn = p.natural_frequencies_hz;
  double f_min = INFINITY, f_max = 0;
  for (Index k = 0; k < fn.size(); ++k)
    if (fn(k) > 0) {
      f_min = std::min(f_min, fn(k));
      f_max = std::max(f_max, fn(k));
    }
  if (!(f_max > 0)) f_min = 1, f_max = 1;
  result.band_low_hz = f_min / 10;
  result.band_hz = o.band_hz > 0 ? o.band_hz : 2 * f_max;
  result.prewarp_hz = f_min;
  return result;
}

// The frequency reference at a rate: the continuous full model G(jw) on the band's grid (log
// spaced, plus each mode's frequency, up to 0.999 x Nyquist), the actuators' columns behind the
// DAC's zero-order hold (which the full model's ZOH discretisation is exactly); each pair's
// error scale; G(0) unless there is a pole at the origin.
Reference reference_at(const scene::ScenePlant& p, const TradeoffOptions& o,
                       const TradeoffResult& result, double rate) {
  const Eigen::VectorXd& fn = p.natural_frequencies_hz;
  Reference ref;
  const double top = std::min(result.band_hz, 0.999 * rate / 2);
  ref.f = lti::log_frequency_grid_hz(result.band_low_hz, std::max(top, 2 * result.band_low_hz),
                                     o.points);
  for (Index k = 0; k < fn.size(); ++k)
    if (fn(k) > result.band_low_hz && fn(k) < top) ref.f.push_back(fn(k));
  std::sort(ref.f.begin(), ref.f.end());
  ref.g = lti::frequency_response(p.plant, ref.f);
  const Index held = static_cast<Index>(p.scene.actuators.size());
  const Response through_hold = lti::frequency_response(
      lti::discretise(p.plant, {lti::DiscretisationMethod::kZeroOrderHold, 1 / rate}), ref.f);
  for (std::size_t k = 0; k < ref.f.size(); ++k)
    ref.g[k].rightCols(held) = through_hold[k].rightCols(held);
  ref.peak = MatrixXd::Zero(p.plant.ny(), p.plant.nu());
  for (const auto& g : ref.g) ref.peak = ref.peak.cwiseMax(g.cwiseAbs());
  ref.peak = error_scale(ref.peak, p.plant);
  try {
    ref.dc = lti::frequency_response(p.plant, {0.0})[0];
  } catch (const std::domain_error&) {
  }
  return ref;
}

// The loop reference at a rate: the full model by exact ZOH in double, its floor samples, its
// open-loop step and its closed loop. A scene whose state-space controller is discrete has it at
// its own rate only: there, and where the exact loop cannot be built, every row says why.
struct LoopReference {
  long steps = 0;
  MatrixXd floor, step, z;
  std::string error;
};

LoopReference loop_reference_at(const scene::ScenePlant& p, const TradeoffOptions& o, double rate) {
  const double scene_rate = p.scene.discretisation.rate_hz;
  const bool discrete_controller = p.state_space && !p.state_space->continuous;
  scene::ScenePlant q = p;
  q.scene.discretisation = {lti::DiscretisationMethod::kZeroOrderHold, rate, 0};
  LoopReference loop;
  loop.steps = std::max(10L, std::lround(o.run_s * rate));
  std::optional<artefact::LoopArtefact> exact;
  if (discrete_controller && rate != scene_rate)
    loop.error =
        "the scene's state-space controller is discrete at " + std::to_string(scene_rate) + " Hz";
  else
    try {
      exact = scene::build_loop_artefact(q, scene::sample_scene(q), artefact::PlantForm::kDense);
    } catch (const std::exception& e) {
      loop.error = e.what();
    }
  if (exact) {
    loop.floor = floor_samples(*exact, loop.steps);
    const KernelRuns k = kernel_runs<double>(*exact, loop.floor, loop.steps);
    loop.step = k.step;
    loop.z = k.z;
  }
  return loop;
}

// One configuration measured against the references: the stored plant's frequency errors, and
// its kernels' open-loop step and closed loop. Returns the timer of its closed-loop step, or an
// empty one when the runtime plant refuses what its scalar cannot hold (pole_precision.hpp):
// then the row says why, as a user's run would.
std::function<double(long)> measure_configuration(const artefact::LoopArtefact& a,
                                                  const scene::SampledScene& sampled,
                                                  bool has_controller, const Reference& ref,
                                                  const LoopReference& loop, Measurement& m) {
  const bool single = m.config.scalar == Scalar::kFloat;
  const lti::DiscreteStateSpace stored = single ? stored_plant<float>(a) : stored_plant<double>(a);
  try {
    m.hinf_error = relative_error(lti::frequency_response(stored, ref.f), ref.g, ref.peak);
  } catch (const std::domain_error&) {
    m.hinf_error = INFINITY;
  }
  m.dc_error = NAN;
  if (ref.dc.size() > 0) try {
      m.dc_error = relative_error(lti::frequency_response(stored, {0.0}), {ref.dc}, ref.peak);
    } catch (const std::domain_error&) {
      m.dc_error = INFINITY;
    }
  KernelRuns k;
  try {
    k = single ? kernel_runs<float>(a, loop.floor, loop.steps)
               : kernel_runs<double>(a, loop.floor, loop.steps);
  } catch (const std::invalid_argument& e) {
    m.skipped = e.what();
    return {};
  }
  m.kernel = k.kernel;
  m.closed_loop_radius =
      has_controller ? sampled.closed_loop.spectral_radius : sampled.plant.spectral_radius;
  m.step_error = worst_row_error(k.step, loop.step, false);
  m.closed_loop_error = worst_row_error(k.z, loop.z, true);
  m.closed_loop_rms_error = worst_rms_ratio(k.z, loop.z);
  return std::move(k.timed);
}

// The sweep so far: its rows, the timers of the measured ones (kept until the timing) and the
// progress. Progress counts the error runs, then every timing pass over the measured
// configurations (known once the sweep is done; until then counted as if none were skipped).
struct SweepState {
  struct Timer {
    std::size_t row;
    std::function<double(long)> timed;
  };
  TradeoffResult& result;
  std::vector<Timer> timers;
  std::size_t done = 0, total = 0;
};

// The scene with one variant's plant sampled by one method at a rate, or why it cannot be.
struct SampledVariant {
  scene::ScenePlant plant;
  std::optional<scene::SampledScene> sampled;
  std::string why;
};

SampledVariant sample_variant(const scene::ScenePlant& p, const Variant& v,
                              const std::string& method, double rate, double prewarp_hz,
                              const std::string& loop_error) {
  SampledVariant c{p, std::nullopt, !v.error.empty() ? v.error : loop_error};
  c.plant.plant = v.sys;
  c.plant.scene.discretisation = {method_of(method), rate,
                                  method == "tustin-prewarp" ? prewarp_hz : 0.0};
  if (c.why.empty()) try {
      if (method == "tustin-prewarp" && !(prewarp_hz < rate / 2))
        throw std::invalid_argument("the pre-warp frequency is above Nyquist");
      c.sampled = scene::sample_scene(c.plant);
    } catch (const std::exception& e) {
      c.why = e.what();
    }
  return c;
}

// The rows of one rate: every variant x method x form x scalar, in that order, each measured or
// kept with the reason it could not be.
void sweep_rate(const scene::ScenePlant& p, const TradeoffOptions& o,
                const std::vector<Variant>& plants, const std::vector<artefact::PlantForm>& forms,
                double rate, SweepState& s) {
  const Reference ref = reference_at(p, o, s.result, rate);
  const LoopReference loop = loop_reference_at(p, o, rate);
  for (const Variant& v : plants)
    for (const std::string& method : o.methods) {
      const SampledVariant c = sample_variant(p, v, method, rate, s.result.prewarp_hz, loop.error);
      for (const artefact::PlantForm form : forms) {
        std::optional<artefact::LoopArtefact> a;
        std::string why = c.why;
        if (why.empty()) try {
            a = scene::build_loop_artefact(c.plant, *c.sampled, form);
          } catch (const std::exception& e) {
            why = e.what();
          }
        for (const std::string& scalar : o.scalars) {
          Measurement m;
          m.config = {.method = method_of(method),
                      .prewarp = method == "tustin-prewarp",
                      .rate_hz = rate,
                      .form = form,
                      .scalar = scalar == "float" ? Scalar::kFloat : Scalar::kDouble,
                      .reduction = reduction_of(v.reduction),
                      .order = v.order};
          m.reduction_bound = v.bound;
          if (o.progress) o.progress(s.done, s.total, m.config);
          ++s.done;
          m.skipped = why;
          if (why.empty())
            if (auto timed = measure_configuration(*a, *c.sampled, scene::has_controller(c.plant),
                                                   ref, loop, m))
              s.timers.push_back({s.result.rows.size(), std::move(timed)});
          s.result.rows.push_back(m);
        }
      }
    }
}

// The timing, round-robin: each pass times every measured configuration once, so that the VM's
// slow and fast phases (tens of seconds) fall on all of them alike, not on whichever was measured
// then; each row gets the median and the spread of its passes, and its share of the period.
void time_round_robin(const TradeoffOptions& o, SweepState& s) {
  s.total = s.done + static_cast<std::size_t>(o.repeats) * s.timers.size();
  std::vector<std::vector<double>> ns(s.timers.size());
  for (int pass = 0; pass < o.repeats; ++pass)
    for (std::size_t k = 0; k < s.timers.size(); ++k) {
      if (o.progress) o.progress(s.done, s.total, s.result.rows[s.timers[k].row].config);
      ++s.done;
      ns[k].push_back(s.timers[k].timed(o.bench_steps));
    }
  for (std::size_t k = 0; k < s.timers.size(); ++k) {
    Measurement& m = s.result.rows[s.timers[k].row];
    std::sort(ns[k].begin(), ns[k].end());
    m.ns_per_step = ns[k].empty() ? NAN : ns[k][ns[k].size() / 2];
    m.ns_min = ns[k].empty() ? NAN : ns[k].front();
    m.ns_max = ns[k].empty() ? NAN : ns[k].back();
    m.period_share = m.ns_per_step * 1e-9 * m.config.rate_hz;
  }
  if (o.progress) o.progress(s.total, s.total, {});
}

}  // namespace

std::string to_string(Scalar s) {
  return s == Scalar::kFloat ? "float" : "double";
}

std::string to_string(Reduction r) {
  for (const auto& [value, text] : kReductionNames)
    if (value == r) return text;
  return "?";
}

std::string Configuration::method_name() const {
  return lti::to_string(method) + (prewarp ? "-prewarp" : "");
}

std::string Configuration::label() const {
  std::ostringstream s;
  s << method_name() << " " << rate_hz << " Hz " << artefact::to_string(form) << " "
    << to_string(scalar) << " " << to_string(reduction) << " " << order;
  return s.str();
}

// The sweep (checked, framed, every rate's rows), then the timing of what it measured.
TradeoffResult run_tradeoff(const scene::ScenePlant& p, const TradeoffOptions& o) {
  const Sweep sweep = checked_sweep(p, o);
  TradeoffResult result = result_frame(p, o);
  const std::vector<Variant> plants = variants(p, o, {result.band_low_hz, result.band_hz});
  const std::size_t configurations =
      plants.size() * sweep.rates.size() * o.methods.size() * o.forms.size() * o.scalars.size();
  SweepState s{result, {}, 0, configurations * static_cast<std::size_t>(1 + o.repeats)};
  for (const double rate : sweep.rates) sweep_rate(p, o, plants, sweep.forms, rate, s);
  time_round_robin(o, s);
  return result;
}

double cost_of(const Measurement& m, Cost cost) {
  return cost == Cost::kStep ? m.ns_per_step : m.period_share;
}

long cheapest_within(const TradeoffResult& r, double budget) {
  long best = -1;
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const Measurement& m = r.rows[k];
    if (!m.skipped.empty() || !(m.hinf_error <= budget)) continue;
    if (best < 0 || cost_of(m, r.cost) < cost_of(r.rows[static_cast<std::size_t>(best)], r.cost))
      best = static_cast<long>(k);
  }
  return best;
}

std::vector<std::size_t> pareto_front(const TradeoffResult& r) {
  std::vector<std::size_t> measured;
  for (std::size_t k = 0; k < r.rows.size(); ++k)
    if (r.rows[k].skipped.empty() && std::isfinite(r.rows[k].hinf_error)) measured.push_back(k);
  std::sort(measured.begin(), measured.end(), [&](auto a, auto b) {
    const double x = cost_of(r.rows[a], r.cost), y = cost_of(r.rows[b], r.cost);
    return x != y ? x < y : r.rows[a].hinf_error < r.rows[b].hinf_error;
  });
  std::vector<std::size_t> front;
  double best_error = INFINITY;
  for (const std::size_t k : measured)
    if (r.rows[k].hinf_error < best_error) {
      front.push_back(k);
      best_error = r.rows[k].hinf_error;
    }
  return front;
}

}  // namespace flexloop::study
