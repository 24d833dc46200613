// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/analyse_scene.hpp"

#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include <unistd.h>

#include "common/input_error.hpp"
#include "controller/design/disk_margins.hpp"
#include "numeric/constants.hpp"
#include "offline/pipeline/closed_loop_by_simulation.hpp"
#include "offline/pipeline/loop_figures.hpp"
#include "offline/pipeline/numerical_health.hpp"
#include "offline/pipeline/provenance.hpp"
#include "offline/pipeline/reduction_error_report.hpp"
#include "offline/pipeline/superelement_provenance.hpp"
#include "offline/report/csv_writer.hpp"
#include "offline/report/plot.hpp"
#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/pole_text.hpp"
#include "plant/lti/state_space_json.hpp"

namespace flexloop::pipeline {

namespace {

namespace lti = plant::lti;
using numeric::kTwoPi;

std::vector<double> to_vector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

void print_matrix(const char* name, const Eigen::MatrixXd& m) {
  std::printf("%s =\n", name);
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    std::printf("  ");
    for (Eigen::Index c = 0; c < m.cols(); ++c) std::printf(" %11.4e", m(r, c));
    std::printf("\n");
  }
}

std::string rate_text(double hz) {
  char text[40];
  std::snprintf(text, sizeof text, "%g Hz", hz);
  return text;
}

double db(double v) {
  return 20 * std::log10(v);
}

// The sampled loop this far above its continuous design and the passive machine somewhere below
// Nyquist is a warning.
constexpr double kSampledExcessWarningDb = 6;

// Largest singular value's peak over the grid: value and frequency.
std::pair<double, double> peak(const Eigen::MatrixXd& sv, const std::vector<double>& f) {
  Eigen::Index i = 0;
  sv.col(0).maxCoeff(&i);
  return {sv(i, 0), f[static_cast<std::size_t>(i)]};
}

}  // namespace

nlohmann::json static_stability_json(const plant::lti::StaticStability& s) {
  const double lc = s.critical_multiplier;
  return {{"stable", s.stable()},
          {"divergent_modes", s.divergent},
          {"flutter_modes", s.flutter},
          {"growth_rate_1_per_s", s.growth_rate},
          {"preloaded", s.preloaded},
          {"critical_buckling_multiplier", lc >= 0 ? nlohmann::json(lc) : nlohmann::json(nullptr)},
          {"preload_over_first_buckling_load",
           lc > 0 ? nlohmann::json(1.0 / lc) : nlohmann::json(nullptr)},
          {"message", plant::lti::to_string(s)}};
}

namespace {

// A disk margin as "gain 0.5 .. 2 (-6.0 .. +6.0 dB), phase +-37 deg at 12.3 Hz" and as JSON.
nlohmann::json disk_margin_json(const controller::design::DiskMargin& m) {
  const bool unbounded = std::isinf(m.gain_high);
  char high[32] = "inf", high_db[32] = "+inf";
  if (!unbounded) {
    std::snprintf(high, sizeof high, "%.3g", m.gain_high);
    std::snprintf(high_db, sizeof high_db, "%+.1f", 20 * std::log10(m.gain_high));
  }
  std::printf("gain %.3g .. %s (%+.1f .. %s dB), phase +-%.1f deg, disk %.3g at %.4g Hz",
              m.gain_low, high, 20 * std::log10(m.gain_low), high_db, m.phase_deg, m.alpha,
              m.frequency_hz);
  return {{"alpha", m.alpha},
          {"gain_low", m.gain_low},
          {"gain_high", unbounded ? nlohmann::json(nullptr) : nlohmann::json(m.gain_high)},
          {"phase_deg", m.phase_deg},
          {"frequency_hz", m.frequency_hz}};
}

// Disk margins of the sampled loop at the actuator commands (controller/design/disk_margins.hpp).
nlohmann::json print_disk_margins(const scene::ScenePlant& p) {
  const auto margins = loop_disk_margins(p);
  std::printf(
      "disk margins at the actuator commands (sampled loop, balanced disk):\n  all at once: ");
  nlohmann::json j = {{"all_loops", disk_margin_json(margins.all_loops)}};
  std::printf("\n  loop at a time:\n");
  nlohmann::json loops = nlohmann::json::object();
  for (std::size_t i = 0; i < margins.loops.size(); ++i) {
    const std::string& name = p.feedback_path.inputs[i];
    std::printf("    %-12s ", name.c_str());
    loops[name] = disk_margin_json(margins.loops[i]);
    std::printf("\n");
  }
  j["loop_at_a_time"] = loops;
  return j;
}

// The per-strut PI design: each strut's k_i, m_i and diagonal gains (the coupled rule prints the
// matrices instead).
void print_strut_gains(const scene::ScenePlant& p, nlohmann::json& j) {
  std::printf(
      "designed per strut (%zu collocated struts): K_P,i = k_i / (m_i w_d^2) - 1, "
      "K_I,i = 2 zeta w_d (1 + K_P,i)\n  %-14s %12s %12s %12s %12s\n",
      p.struts.size(), "strut", "k_i [N/m]", "m_i [kg]", "K_P,i", "K_I,i [1/s]");
  nlohmann::json struts = nlohmann::json::array();
  for (std::size_t i = 0; i < p.struts.size(); ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    const double k = p.struts[i].stiffness, m = 1.0 / p.struts[i].inverse_mass;
    std::printf("  %-14s %12.5g %12.5g %12.5g %12.5g\n", p.scene.actuators[i].c_str(), k, m,
                p.gains.K_P(e, e), p.gains.K_I(e, e));
    struts.push_back({{"actuator", p.scene.actuators[i]}, {"stiffness", k}, {"mass", m}});
  }
  j["pi_design"] = "per_strut";
  j["struts"] = struts;
}

// The controller: the PI design (its gains), or the user's state space (its size and poles).
void print_controller(const scene::ScenePlant& p, nlohmann::json& j) {
  const auto& c = p.scene.controller;
  const bool continuous = scene::has_continuous_loop(p);
  if (scene::has_pi_controller(p)) {
    std::printf("PI force feedback: omega_d = 2 pi x %g Hz, zeta = %g, leak %s\n", c.omega_d_hz,
                c.zeta, c.leak_hz > 0 ? (std::to_string(c.leak_hz) + " Hz").c_str() : "none");
    if (p.struts.empty()) {
      print_matrix("K_P", p.gains.K_P);
      print_matrix("K_I [1/s]", p.gains.K_I);
    } else {
      print_strut_gains(p, j);
    }
    j["K_P"] = lti::matrix_to_json(p.gains.K_P);
    j["K_I"] = lti::matrix_to_json(p.gains.K_I);
    j["controller_settings"] = {
        {"omega_d_hz", c.omega_d_hz}, {"zeta", c.zeta}, {"leak_hz", c.leak_hz}};
    return;
  }
  const auto& d = p.state_space->discrete;
  std::printf(
      "state-space controller %s: %ld states, %ld sensors -> %ld actuators, %s%s, "
      "anti-windup %s\n",
      c.file.c_str(), static_cast<long>(d.sys.nx()), static_cast<long>(d.sys.nu()),
      static_cast<long>(d.sys.ny()), continuous ? "continuous, discretised with " : "discrete at ",
      continuous ? lti::to_string(d.method).c_str() : rate_text(1 / d.dt).c_str(),
      c.anti_windup.c_str());
  std::printf("controller poles (discrete, at the scene's rate): spectral radius %.6g\n",
              d.spectral_radius);
  j["controller_settings"] = {{"file", c.file},
                              {"states", d.sys.nx()},
                              {"time", continuous ? "continuous" : "discrete"},
                              {"anti_windup", c.anti_windup},
                              {"spectral_radius", d.spectral_radius}};
}

// The continuous loop's poles: the closed loop's without the floor's integrator states (at s = 0,
// driven by the floor only, untouched by the controller).
void print_closed_loop_poles(const scene::ScenePlant& p, nlohmann::json& j) {
  const bool continuous = scene::has_continuous_loop(p);
  const Eigen::VectorXcd& poles = p.loop.poles;
  const Eigen::Index floor_states = continuous ? p.closed_loop.nx() - poles.size() : 0;
  // A pole within round-off of s = 0 is an integrator (the pure PI's): printed as one, without
  // a damping (plant/lti/pole_text.hpp has the tolerance).
  const double at_zero = lti::integrator_tolerance(poles);
  long integrators = 0;
  for (const auto& s : poles) integrators += lti::is_integrator(s, at_zero);
  if (continuous)
    std::printf("closed-loop poles (%ld%s%s):\n", static_cast<long>(poles.size()),
                integrators > 0
                    ? (", " + std::to_string(integrators) + " of them integrators at s = 0").c_str()
                    : "",
                floor_states > 0 ? (", besides " + std::to_string(floor_states) +
                                    " floor integrator states at s = 0")
                                       .c_str()
                                 : "");
  nlohmann::json pj = nlohmann::json::array();
  for (const auto& s : poles) {
    if (lti::is_integrator(s, at_zero))
      std::printf("  %+14.6e %+14.6ej rad/s   %9.4f Hz  %s\n", 0.0, 0.0, 0.0,
                  lti::integrator_text(s).c_str());
    else
      std::printf("  %+14.6e %+14.6ej rad/s   %9.4f Hz  damping %.4f\n", s.real(), s.imag(),
                  std::abs(s) / kTwoPi, lti::damping_ratio(s, at_zero));
    pj.push_back({s.real(), s.imag()});
  }
  j["floor_integrator_states"] = floor_states;
  j["closed_loop_poles"] = pj;
}

// The continuous loop's stability, and the leak that would give it (or the margin the present
// one has).
void print_continuous_stability(const scene::ScenePlant& p, nlohmann::json& j) {
  const auto& c = p.scene.controller;
  const bool pi = scene::has_pi_controller(p), continuous = scene::has_continuous_loop(p);
  const auto min_leak = pi ? scene::minimum_stable_leak_hz(p) : std::optional<double>();
  if (!continuous)
    std::printf("continuous loop: none (the controller is given in discrete time)\n");
  else if (!pi)
    std::printf(p.loop.stable() ? "continuous loop: stable\n"
                                : "continuous loop: UNSTABLE, %d poles in the right half plane "
                                  "(fastest e^(%.3g t))\n",
                p.loop.unstable, p.loop.largest_real_part);
  else if (p.loop.stable())
    std::printf("continuous loop: stable");
  else
    std::printf("continuous loop: UNSTABLE, %d poles in the right half plane (fastest e^(%.3g t))",
                p.loop.unstable, p.loop.largest_real_part);
  if (!pi)
    ;  // the leak is the PI's
  else if (min_leak && *min_leak > 0)
    std::printf(
        "; needs leak_hz > %.4g (has %g)%s\n", *min_leak, c.leak_hz,
        p.scene.gravity_preload ? ": the gravity preload's geometric stiffness is negative" : "");
  else if (min_leak)
    std::printf(p.loop.stable() ? " without a leak\n"
                                : "; it would be without a leak: check omega_d_hz and zeta\n");
  else if (pi)
    std::printf(p.loop.stable() ? " (no leak up to omega_d would be)\n"
                                : "; no leak up to omega_d makes it stable\n");
  j["continuous_loop_stable"] =
      continuous ? nlohmann::json(p.loop.stable()) : nlohmann::json(nullptr);
  j["minimum_stable_leak_hz"] = min_leak ? nlohmann::json(*min_leak) : nlohmann::json(nullptr);
}

// The sampled loop's figures as analysis.json has them.
nlohmann::json sampled_loop_json(const scene::SampledLoop& s) {
  const auto& st = s.stability;
  nlohmann::json sj = {{"rate_hz", s.rate_hz},
                       {"method", lti::to_string(s.method)},
                       {"feedthrough_delay_samples", s.hardware.feedthrough_delay},
                       {"spectral_radius", st.spectral_radius},
                       {"largest_inner_radius", st.largest_inner_radius},
                       {"unit_circle_tolerance", st.tolerance},
                       {"unstable_poles", st.unstable},
                       {"marginal_poles", st.marginal},
                       {"stable", st.stable()}};
  nlohmann::json zp = nlohmann::json::array();
  for (const auto& z : st.poles) zp.push_back({z.real(), z.imag()});
  sj["poles"] = zp;
  return sj;
}

// An unstable sampled loop: how many poles outside, and the rate or omega_d that would hold.
void print_sampled_loop_remedy(const scene::ScenePlant& p, const scene::SampledLoop& s,
                               nlohmann::json& sj) {
  const auto& st = s.stability;
  std::printf(": UNSTABLE, %d pole%s outside the unit circle", st.unstable,
              st.unstable == 1 ? "" : "s");
  const scene::SampledLoopRemedy r = scene::stable_sampled_loop_remedy(p);
  if (r.rate_hz) std::printf("; stable at rate_hz = %g", *r.rate_hz);
  if (r.omega_d_hz)
    std::printf("%s omega_d_hz <= %g at %g Hz", r.rate_hz ? " or with" : "; stable with",
                *r.omega_d_hz, s.rate_hz);
  std::printf("\n");
  sj["stable_rate_hz"] = r.rate_hz ? nlohmann::json(*r.rate_hz) : nlohmann::json(nullptr);
  sj["stable_omega_d_hz"] = r.omega_d_hz ? nlohmann::json(*r.omega_d_hz) : nlohmann::json(nullptr);
}

// The loop as it runs: sampled at the scene's rate (controller/design/sampled_loop_stability),
// printed and put into j["sampled_loop"] (null when the discretisation is refused).
std::optional<SampledLoopStability> print_sampled_loop(const scene::ScenePlant& p,
                                                       nlohmann::json& j) {
  j["sampled_loop"] = nullptr;
  try {
    const scene::SampledLoop s = scene::sampled_loop(p);
    const auto& st = s.stability;
    const int delay = s.hardware.feedthrough_delay;
    std::printf(
        "sampled loop at %g Hz (%s, the controller as it runs, the held command%s): spectral "
        "radius %.6g",
        s.rate_hz, lti::to_string(s.method).c_str(),
        delay > 0
            ? (", " + std::to_string(delay) + (delay == 1 ? " sample" : " samples") + " of delay")
                  .c_str()
            : "",
        st.spectral_radius);
    if (st.marginal > 0)
      std::printf(" (%d pole%s on the unit circle%s; the poles inside it within |z| <= %.6g)",
                  st.marginal, st.marginal == 1 ? "" : "s",
                  scene::has_pi_controller(p) && p.scene.controller.leak_hz == 0
                      ? ", marginal: the pure integrator's at z = 1"
                      : ", marginal",
                  st.largest_inner_radius);
    nlohmann::json sj = sampled_loop_json(s);
    if (st.stable())
      std::printf(": stable\n");
    else
      print_sampled_loop_remedy(p, s, sj);
    j["sampled_loop"] = sj;
    return st;
  } catch (const common::InputError& e) {
    std::printf("sampled loop: not formed: %s\n", e.what());
  }
  return std::nullopt;
}

// The PI design, the continuous loop's poles and stability, and the loop as it runs (sampled):
// printed and put into j. Returns the sampled loop's stability when it was formed.
std::optional<SampledLoopStability> analyse_loop(const scene::ScenePlant& p, nlohmann::json& j) {
  print_controller(p, j);
  print_closed_loop_poles(p, j);
  print_continuous_stability(p, j);
  const std::optional<SampledLoopStability> sampled = print_sampled_loop(p, j);
  const bool stable = closed_loop_stable(p, sampled);
  std::printf("closed loop: %s\n",
              stable
                  ? (scene::has_continuous_loop(p) ? "stable (continuous, and sampled as it runs)"
                                                   : "stable (sampled as it runs)")
                  : "UNSTABLE as it runs: sim, plant, controller and hil refuse this scene");
  j["closed_loop_stable"] = stable;
  if (stable) {
    try {
      j["disk_margins"] = print_disk_margins(p);
    } catch (const std::domain_error& e) {  // a loop pole on the unit circle at a grid frequency
      std::printf("disk margins: not formed: %s\n", e.what());
    }
  }
  return sampled;
}

}  // namespace

namespace {

// A controller FMU's sampled closed loop at `frequencies_hz`, by simulation
// (closed_loop_by_simulation.hpp): printed and put into j["closed_loop_by_simulation"]. Empty when
// the loop diverged (it is then said to be unstable).
// @throws flexloop::InputError naming the FMU when it fails during the runs.
std::vector<Eigen::MatrixXcd> closed_loop_of_fmu(const scene::ScenePlant& p,
                                                 const std::vector<double>& frequencies_hz,
                                                 nlohmann::json& j) {
  const std::string& file = p.scene.controller.file;
  std::printf(
      "controller: FMU %s: compiled code, no matrices to see into: disk margins are skipped; "
      "the sampled closed loop by simulation (an impulse per disturbance channel, from rest, "
      "without the hardware's effects)\n",
      file.c_str());
  const artefact::LoopArtefact a =
      scene::build_loop_artefact(p, scene::sample_scene(p), artefact::PlantForm::kDense);
  if (a.disturbances() == 0 || a.performance() == 0) {
    std::printf("  no floor or no performance channel: no closed loop to measure\n");
    return {};
  }
  const ImpulseSettings settings;
  // Progress on a terminal only (a lightly damped loop runs up to max_samples per channel).
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const auto r =
      closed_loop_by_simulation(a, frequencies_hz, settings, [&](Eigen::Index c, long n) {
        if (tty)
          std::fprintf(stderr, "\r  closed loop by simulation: channel %ld of %ld, %ld samples  ",
                       static_cast<long>(c + 1), static_cast<long>(a.disturbances()), n);
      });
  if (tty) std::fprintf(stderr, "\r%70s\r", "");
  if (!r.controller_failure.empty())
    throw common::InputError(
        file, "the controller FMU failed in the analysis's run: " + r.controller_failure);
  const double seconds = static_cast<double>(r.samples) * a.dt();
  j["closed_loop_by_simulation"] = {{"impulse", settings.amplitude},
                                    {"samples_per_channel", r.samples},
                                    {"decayed", r.decayed},
                                    {"diverged", r.diverged},
                                    {"tail_over_peak", r.tail},
                                    {"constant_tail_over_peak", r.constant_tail},
                                    {"decay_per_sample", r.decay_per_sample},
                                    {"truncation_bound_over_peak", r.truncation_bound}};
  if (r.diverged) {
    std::printf(
        "sampled loop by simulation: UNSTABLE: a response grew past 1e12 of its first peak "
        "within %ld samples (%.4g s); no closed loop drawn\n",
        r.samples, seconds);
    return {};
  }
  const double tau = r.decay_per_sample > 0 && r.decay_per_sample < 1
                         ? -a.dt() / std::log(r.decay_per_sample)
                         : std::numeric_limits<double>::infinity();
  if (r.decayed) {
    std::printf(
        "sampled loop by simulation: the responses settled to %.0e of their peak in %ld samples "
        "(%.4g s); slowest decay %.6f per sample (time constant %.4g s); what is left out is at "
        "most %.1e of the peak\n",
        settings.decay_tolerance, r.samples, seconds, r.decay_per_sample, tau, r.truncation_bound);
    if (r.constant_tail > settings.decay_tolerance)
      std::printf(
          "  the frame's response settles to a constant (%.2e of its peak), not to zero: a "
          "closed-loop pole at z = 1 (an integrator the loop leaves undamped), infinite at DC\n",
          r.constant_tail);
  } else
    std::printf(
        "sampled loop by simulation: NOT DECAYED after %ld samples (%.4g s): the last block is "
        "%.1e of the peak (decay %.6f per sample): a lightly damped or marginally stable loop; "
        "the responses below are truncated there\n",
        r.samples, seconds, r.tail, r.decay_per_sample);
  return r.response;
}

}  // namespace

namespace {

// The passive machine: its natural frequencies (and what the preload does to each), its statics.
void print_passive_machine(const scene::ScenePlant& p, nlohmann::json& j) {
  const scene::Scene& sc = p.scene;
  std::printf("passive natural frequencies%s [Hz]:",
              sc.gravity_preload ? " with the gravity preload" : "");
  for (Eigen::Index i = 0; i < p.natural_frequencies_hz.size(); ++i)
    std::printf(" %.4f", p.natural_frequencies_hz(i));
  std::printf("\n");
  j["natural_frequencies_hz"] = to_vector(p.natural_frequencies_hz);
  if (sc.gravity_preload) {
    // The same scene unloaded, to show what the preload (G-bar) does to each mode.
    scene::Scene unloaded = sc;
    unloaded.gravity_preload = false;
    const auto u = scene::build_scene_plant(unloaded);
    std::printf("gravity preload: static equilibrium in %d Newton steps; shift per mode [Hz]:",
                p.equilibrium_iterations);
    const Eigen::VectorXd shift = p.natural_frequencies_hz - u.natural_frequencies_hz;
    for (Eigen::Index i = 0; i < shift.size(); ++i) std::printf(" %+.3e", shift(i));
    std::printf("\n");
    j["natural_frequencies_unloaded_hz"] = to_vector(u.natural_frequencies_hz);
    j["gravity_frequency_shift_hz"] = to_vector(shift);
  }
  j["static_stability"] = static_stability_json(p.statics);
}

// The controller's and the closed loop's matrices into analysis.json: continuous where the loop
// has a continuous form, else sampled (`sampled`: the scene at its rate).
void put_loop_matrices(const scene::ScenePlant& p,
                       const std::optional<scene::SampledScene>& sampled, nlohmann::json& j) {
  if (!scene::has_controller(p)) return;
  if (scene::has_continuous_loop(p)) {
    j["controller"] = lti::to_json(p.controller);
    j["closed_loop"] = lti::to_json(p.closed_loop);
  } else {
    j["controller"] = lti::to_json(p.state_space->discrete);
    j["closed_loop"] = lti::to_json(sampled->closed_loop);
  }
}

void print_numerical_health(const scene::ScenePlant& p,
                            const std::optional<SampledLoopStability>& sampled_loop,
                            nlohmann::json& j) {
  try {
    const auto health = numerical_health(p, scene::sample_scene(p).plant, sampled_loop);
    print_health(health);
    j["numerical_health"] = health_json(health);
  } catch (const common::InputError& e) {
    std::printf("numerical health: the plant is not sampled: %s\n", e.what());
  }
}

// The passive path floor -> frame G11 and the closed loop T on the grid f and at each passive
// resonance fr (T empty without a closed loop), with their singular values.
struct Responses {
  std::vector<double> f, fr;
  lti::StateSpace g11;
  std::vector<Eigen::MatrixXcd> G, T, T_at_resonances;
  Eigen::MatrixXd sv_open, sv_closed;
  std::optional<SampledAgainstDesign> as_run;  // a continuous loop's design against its run
  double rate_hz = 0;
  bool closed() const { return !T.empty(); }
};

// The closed loop's responses only when there is one (a scene without a controller: the passive
// machine alone). A controller FMU's by simulation, at both sets of frequencies at once.
Responses frequency_responses(const scene::ScenePlant& p,
                              const std::optional<scene::SampledScene>& sampled,
                              const FrequencyGrid& grid, nlohmann::json& j) {
  Responses r;
  r.f = lti::with_resonances(lti::log_frequency_grid_hz(grid.f_min_hz, grid.f_max_hz, grid.points),
                             p.natural_frequencies_hz);
  r.fr = to_vector(p.natural_frequencies_hz);
  r.g11 = floor_to_performance(p);
  r.G = lti::frequency_response(r.g11, r.f);
  if (scene::has_controller(p)) {
    const scene::SampledScene* s = sampled ? &*sampled : nullptr;
    r.T = closed_loop_response(p, s, r.f);
    r.T_at_resonances = closed_loop_response(p, s, r.fr);
  } else if (scene::has_fmu_controller(p)) {
    std::vector<double> both = r.f;
    both.insert(both.end(), r.fr.begin(), r.fr.end());
    r.T = closed_loop_of_fmu(p, both, j);
    if (!r.T.empty()) {
      r.T_at_resonances.assign(r.T.begin() + static_cast<std::ptrdiff_t>(r.f.size()), r.T.end());
      r.T.resize(r.f.size());
    }
  }
  r.sv_open = lti::singular_values(r.G);
  r.sv_closed = r.closed() ? lti::singular_values(r.T) : Eigen::MatrixXd();
  if (r.closed() && scene::has_continuous_loop(p)) {
    r.as_run = sampled_against_design(p, scene::sample_scene(p), r.f);
    r.rate_hz = p.scene.discretisation.rate_hz;
  }
  return r;
}

// singular_values.csv and .png: every singular value of G11 and of T over the grid.
void write_singular_values(const Responses& r, const std::string& scene_name,
                           const std::string& controller_name, const std::string& dir) {
  std::vector<std::string> header{"frequency_hz"};
  std::vector<std::vector<double>> cols{r.f};
  for (const auto& [name, sv] : {std::pair{"open", &r.sv_open}, std::pair{"closed", &r.sv_closed}})
    for (Eigen::Index k = 0; k < sv->cols(); ++k) {
      header.push_back(std::string(name) + " sigma" + std::to_string(k + 1) + " [dB]");
      std::vector<double> col;
      for (Eigen::Index i = 0; i < sv->rows(); ++i) col.push_back(db((*sv)(i, k)));
      cols.push_back(col);
    }
  report::write_csv_columns(dir + "singular_values.csv", header, cols);
  std::vector<report::SigmaSeries> systems{
      {"open loop (passive)", r.f, r.sv_open, "lines lw 2 dt 1"}};
  if (r.closed())
    systems.push_back(
        {"closed loop (" + controller_name + ")", r.f, r.sv_closed, "lines lw 2 dt 2"});
  if (r.as_run)
    systems.push_back(
        {"closed loop as it runs, sampled at " + report::format_number(r.rate_hz) + " Hz (largest)",
         r.as_run->f, r.as_run->sampled, "lines lw 2 dt 3"});
  report::plot_singular_values(
      {scene_name + ": floor acceleration -> frame acceleration, singular values", "", "", true,
       false},
      systems, dir + "singular_values.png");
}

// transmissibility.csv and .png: per channel, disturbance i -> performance output i.
void write_transmissibility(const Responses& r, const std::string& scene_name,
                            const std::string& dir) {
  const Eigen::Index n = std::min(r.g11.nu(), r.g11.ny());
  std::vector<std::string> th{"frequency_hz"};
  std::vector<std::vector<double>> tc{r.f};
  std::vector<report::Series> series;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::string name = r.g11.outputs[i] + " / " + r.g11.inputs[i];
    const std::string colour = " lc " + std::to_string(i + 1);
    std::vector<double> open;
    for (std::size_t k = 0; k < r.f.size(); ++k) open.push_back(db(std::abs(r.G[k](i, i))));
    th.push_back(name + " open [dB]");
    tc.push_back(open);
    series.push_back({name + " open", r.f, open, "lines lw 2 dt 1" + colour});
    if (!r.closed()) continue;
    std::vector<double> closed_db;
    for (std::size_t k = 0; k < r.f.size(); ++k) closed_db.push_back(db(std::abs(r.T[k](i, i))));
    th.push_back(name + " closed [dB]");
    tc.push_back(closed_db);
    series.push_back({name + " closed", r.f, closed_db, "lines lw 2 dt 2" + colour});
  }
  report::write_csv_columns(dir + "transmissibility.csv", th, tc);
  report::plot_lines({scene_name + (r.closed() ? ": per-channel floor -> frame transmissibility "
                                                 "(solid open, dashed closed)"
                                               : ": per-channel floor -> frame transmissibility"),
                      "frequency [Hz]", "|T_ii| [dB]", true, false, 1200, 700},
                     series, dir + "transmissibility.png");
}

// The largest singular value's peaks, and what the controller does at each passive resonance
// (responses evaluated exactly there).
void print_sigma_peaks(const Responses& r, nlohmann::json& j) {
  const auto [open_peak, open_f] = peak(r.sv_open, r.f);
  if (!r.closed()) {
    std::printf("largest singular value: peak %.1f dB at %.2f Hz\n", db(open_peak), open_f);
    j["sigma_max_peak"] = {{"open_db", db(open_peak)}, {"open_hz", open_f}};
    return;
  }
  const Eigen::MatrixXd at_open = lti::singular_values(lti::frequency_response(r.g11, r.fr));
  const Eigen::MatrixXd at_closed = lti::singular_values(r.T_at_resonances);
  std::printf("at the passive resonances: largest singular value open -> closed loop\n");
  nlohmann::json at = nlohmann::json::array();
  for (std::size_t i = 0; i < r.fr.size(); ++i) {
    const double o = db(at_open(static_cast<Eigen::Index>(i), 0)),
                 cl = db(at_closed(static_cast<Eigen::Index>(i), 0));
    std::printf("  %8.3f Hz  %7.1f dB -> %7.1f dB  (%+.1f dB)\n", r.fr[i], o, cl, cl - o);
    at.push_back({{"frequency_hz", r.fr[i]}, {"open_db", o}, {"closed_db", cl}});
  }
  j["sigma_max_at_resonances"] = at;
  const auto [closed_peak, closed_f] = peak(r.sv_closed, r.f);
  std::printf(
      "largest singular value: open loop peak %.1f dB at %.2f Hz, closed loop peak %.1f "
      "dB at %.2f Hz\n",
      db(open_peak), open_f, db(closed_peak), closed_f);
  j["sigma_max_peak"] = {{"open_db", db(open_peak)},
                         {"open_hz", open_f},
                         {"closed_db", db(closed_peak)},
                         {"closed_hz", closed_f}};
}

// The loop as it runs (sampled) against its continuous design: the figures above are the
// design's; a run sees the sampled loop's. More than 6 dB above both the design and the passive
// machine anywhere below Nyquist is said loudly, with what usually causes it and what to do.
void print_sampled_against_design(const Responses& r, nlohmann::json& j) {
  if (!r.as_run || r.as_run->f.empty()) return;
  const SampledAgainstDesign& a = *r.as_run;
  Eigen::Index at = 0;
  a.sampled.maxCoeff(&at);
  const double peak_hz = a.f[static_cast<std::size_t>(at)];
  std::printf(
      "the loop as it runs, sampled at %g Hz: largest singular value peak %.1f dB at %.2f Hz; "
      "from %.3g to %.3g Hz above both its continuous design and the passive machine by at most "
      "%+.1f dB (at %.2f Hz)\n",
      r.rate_hz, db(a.sampled(at)), peak_hz, a.judged_from_hz, a.judged_to_hz, a.excess_db,
      a.excess_hz);
  j["sampled_loop_response"] = {{"rate_hz", r.rate_hz},
                                {"peak_db", db(a.sampled(at))},
                                {"peak_hz", peak_hz},
                                {"judged_from_hz", a.judged_from_hz},
                                {"judged_to_hz", a.judged_to_hz},
                                {"excess_over_design_db", a.excess_db},
                                {"excess_hz", a.excess_hz}};
  if (a.excess_db <= kSampledExcessWarningDb) return;
  const double nyquist_hz = 0.5 * r.rate_hz;
  std::printf(
      "WARNING: the loop as it runs amplifies what its design and the passive machine do not "
      "(%+.1f dB at %.2f Hz): sim, hil and a campaign see the sampled loop. ",
      a.excess_db, a.excess_hz);
  if (a.modes_above_nyquist > 0)
    std::printf(
        "%d of the plant's modes lie above Nyquist (%g Hz): a sampled force loop cannot act on "
        "them as designed. Residualise them ([plant] reduction = \"modal-dc\", below_hz = %g: "
        "their static compliance kept) or raise the rate\n",
        a.modes_above_nyquist, nyquist_hz, 0.5 * nyquist_hz);
  else
    std::printf("Raise the rate, or design the controller for the sampled loop\n");
}

std::string controller_name(const scene::ScenePlant& p) {
  if (scene::has_fmu_controller(p)) return "controller FMU, by simulation";
  if (scene::has_pi_controller(p)) return "PI force feedback";
  return scene::has_continuous_loop(p) ? "state space" : "state space, sampled";
}

}  // namespace

void analyse_scene(const std::string& scene_path, const std::string& out_dir,
                   const FrequencyGrid& grid, const AnalyseOptions& options) {
  const scene::Scene sc = scene::load_scene(scene_path);
  const ReductionErrorBand band(options.reduction_error ? grid.f_max_hz : 0.0);
  const scene::ScenePlant p = scene::build_scene_plant(sc);
  std::filesystem::create_directories(out_dir);
  const std::string dir = out_dir + "/";

  std::printf("scene %s: model %s, %ld states, %ld inputs, %ld outputs\n", sc.name.c_str(),
              sc.model_path.c_str(), static_cast<long>(p.plant.nx()),
              static_cast<long>(p.plant.nu()), static_cast<long>(p.plant.ny()));
  nlohmann::json j;
  const auto write_analysis_json = [&] {
    j["provenance"] = make_provenance(scene_path, "flexloop analyse");
    j["provenance"]["model"] = make_provenance(sc.model_path, "flexloop analyse");
    if (!p.model.superelements.empty())
      j["provenance"]["model"]["superelements"] = superelement_provenance(p.model);
    lti::write_json_atomically(dir + "analysis.json", j);
  };
  print_passive_machine(p, j);
  if (!p.statics.stable()) {
    // The loop commands refuse this plant (scene::require_stable_loop): no loop to analyse.
    std::printf("passive plant: UNSTABLE: %s\n", plant::lti::to_string(p.statics).c_str());
    std::printf("build, sim, plant, controller and hil refuse this scene; no loop analysed\n");
    j["open_loop"] = lti::to_json(p.plant);
    write_analysis_json();
    std::printf("wrote %sanalysis.json\n", dir.c_str());
    return;
  }
  std::printf("passive plant: %s\n", plant::lti::to_string(p.statics).c_str());

  const bool controlled = scene::has_controller(p);
  std::optional<SampledLoopStability> sampled_loop;
  if (controlled)
    sampled_loop = analyse_loop(p, j);
  else if (!scene::has_fmu_controller(p))
    std::printf("controller: none (the passive plant alone: no design, no closed loop)\n");
  j["open_loop"] = lti::to_json(p.plant);
  // A controller given in discrete time has the sampled closed loop only (z = e^{j w T}).
  const std::optional<scene::SampledScene> sampled = controlled && !scene::has_continuous_loop(p)
                                                         ? std::optional(scene::sample_scene(p))
                                                         : std::nullopt;
  put_loop_matrices(p, sampled, j);
  print_numerical_health(p, sampled_loop, j);

  const Responses r = frequency_responses(p, sampled, grid, j);
  write_singular_values(r, sc.name, controller_name(p), dir);
  write_transmissibility(r, sc.name, dir);
  print_sigma_peaks(r, j);
  print_sampled_against_design(r, j);
  if (options.reduction_error && !p.model.superelements.empty())
    j["reduction_error"] =
        report_reduction_error(p.model, p.lin, p.plant.inputs, p.plant.outputs, r.f, grid.f_max_hz);
  write_analysis_json();
  std::printf(
      "wrote %s{analysis.json, singular_values.csv, singular_values.png, "
      "transmissibility.csv, transmissibility.png}\n",
      dir.c_str());
}

}  // namespace flexloop::pipeline
