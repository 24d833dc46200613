// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/scene_plant.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

#include "common/input_error.hpp"
#include "common/toml_reader.hpp"
#include "numeric/constants.hpp"
#include "offline/scene/collocated_struts.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/model_reduction.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/model/static_equilibrium.hpp"

namespace flexloop::scene {

namespace {

using numeric::kTwoPi;

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// "file:line" of [table] key in the scene file (of the table when the key is absent; the file
// alone when neither is there or the file cannot be read again, e.g. a scene parsed from text).
std::string scene_place(const Scene& sc, const char* table, const char* key) {
  try {
    const toml::table root =
        common::parse_toml(common::read_input_file(sc.file, "scene file"), sc.file);
    const auto* t = root.get(table);
    if (!t || !t->as_table()) return sc.file;
    const common::TomlReader r(*t->as_table(), sc.file, table);
    return r.place(r.get(key));
  } catch (const std::exception&) {
    return sc.file;
  }
}

// ", d sample(s) of delay" (sensor + transport), or nothing.
std::string delay_text(int d) {
  if (d == 0) return "";
  return ", " + std::to_string(d) + (d == 1 ? " sample" : " samples") + " of delay";
}

// The rounding of a bound at 3 significant digits, down (a stable omega_d stays stable below).
double round_down_3(double v) {
  const double step = std::pow(10.0, std::floor(std::log10(v)) - 2);
  return std::floor(v / step) * step;
}

// The design with the scene's zeta and leak at another omega_d (the scene's own gains are
// gains_at(p, its omega_d_hz)): the coupled rule from Mdd, Kdd, or per strut from p.struts.
controller::design::PiGains gains_at(const ScenePlant& p, double omega_d_hz) {
  const auto& c = p.scene.controller;
  const controller::design::PiForceFeedbackSettings s{kTwoPi * omega_d_hz, c.zeta,
                                                      kTwoPi * c.leak_hz};
  if (!p.struts.empty()) return controller::design::design_pi_force_feedback_per_strut(p.struts, s);
  const int nd = p.model.nd();
  return controller::design::design_pi_force_feedback(p.lin.M.topLeftCorner(nd, nd),
                                                      p.lin.K.topLeftCorner(nd, nd), s);
}

}  // namespace

ScenePlant build_scene_plant(const Scene& scene, const ScenePlantOptions& options) {
  return build_scene_plant(scene, plant::model::load_model(scene.model_path), options);
}

ScenePlant build_scene_plant(const Scene& scene, plant::model::Model machine,
                             const ScenePlantOptions& options) {
  namespace model = plant::model;
  ScenePlant p;
  p.scene = scene;
  p.model = std::move(machine);
  model::Model& m = p.model;
  if (options.without_damping)
    for (auto& el : m.elements) el.damping.setZero();
  // The preload is the model's gravity (standard gravity along -z when the model gives none);
  // without it the model is linearised unloaded.
  if (scene.gravity_preload) {
    if (m.gravity.norm() == 0) m.gravity(m.dim - 1) = -9.80665;
  } else {
    m.gravity.setZero();
  }
  model::OperatingPoint op = model::model_operating_point(m);
  if (scene.gravity_preload) {
    const auto eq = model::static_equilibrium(m);
    op = eq.op;
    p.equilibrium_iterations = eq.iterations;
  }
  p.lin = model::linearise(m, op);
  const int nd = m.nd();
  const Eigen::MatrixXd Mdd = p.lin.M.topLeftCorner(nd, nd);
  const auto modes =
      plant::lti::natural_modes(Mdd, (p.lin.K + p.lin.N + p.lin.G).topLeftCorner(nd, nd));
  p.natural_frequencies_hz = modes.frequencies_hz;
  p.statics = plant::lti::static_stability(modes, p.lin.K.topLeftCorner(nd, nd),
                                           p.lin.G.topLeftCorner(nd, nd));

  try {
    p.plant = plant::lti::build_state_space(m, p.lin, concat(scene.disturbances, scene.actuators),
                                            concat(scene.performance, scene.sensors));
  } catch (const common::InputError& e) {
    throw common::InputError(scene.file, std::string("[plant]: ") + e.what());
  }
  if (!scene.reduction.method.empty()) p.plant = reduced_plant(p.plant, scene);
  p.partition = {static_cast<Eigen::Index>(scene.disturbances.size()),
                 static_cast<Eigen::Index>(scene.performance.size())};
  // No controller: the plant runs alone (an external controller, an open-loop study).
  if (!has_controller(p)) return p;
  if (scene.controller.type == "state_space") {
    p.state_space = load_scene_controller(scene);
    p.feedback_path = plant::lti::build_state_space(m, p.lin, scene.actuators, scene.sensors);
    if (!p.state_space->continuous) return p;
    p.controller = *p.state_space->continuous;
    try {
      p.closed_loop = plant::lti::close_loop(p.plant, p.controller, p.partition);
      p.loop = controller::design::loop_stability(p.feedback_path, p.controller,
                                                  state_space_reference_rad_s(scene));
    } catch (const std::invalid_argument& e) {
      throw common::InputError(scene.controller.file_place,
                               std::string("[controller]: ") + e.what());
    }
    return p;
  }

  // Each actuator with its own strut's force sensor; the coupled rule (Kdd, Mdd) where the struts
  // are the dynamic coordinates, else one loop per strut (controller/design/pi_force_feedback.hpp).
  require_collocated_pairs(scene, m);
  if (!struts_are_the_coordinates(scene, m)) p.struts = collocated_struts(scene, m, p.lin);
  p.gains = options.pi_gains ? *options.pi_gains : gains_at(p, scene.controller.omega_d_hz);
  p.controller = controller::design::pi_state_space(p.gains, scene.sensors, scene.actuators);
  p.closed_loop = plant::lti::close_loop(p.plant, p.controller, p.partition);
  // The floor held still: no prescribed inputs, so no floor integrator states.
  p.feedback_path = plant::lti::build_state_space(m, p.lin, scene.actuators, scene.sensors);
  p.loop = controller::design::loop_stability(p.feedback_path, p.gains);
  return p;
}

std::optional<double> minimum_stable_leak_hz(const ScenePlant& p) {
  const double wd = kTwoPi * p.scene.controller.omega_d_hz;
  const auto w = controller::design::minimum_stable_leak_rad_s(p.feedback_path, p.gains, wd);
  if (!w) return std::nullopt;
  return *w / kTwoPi;
}

double state_space_reference_rad_s(const Scene& scene) {
  return std::numbers::pi * scene.discretisation.rate_hz;
}

namespace {

// The loop at a rate, with the linear part of the scene's hardware.
SampledLoop sampled_loop_frame(const ScenePlant& p, double rate_hz) {
  const auto& d = p.scene.discretisation;
  const auto& e = p.scene.effects;
  SampledLoop s;
  s.rate_hz = rate_hz;
  s.method = d.method;
  // As the runtime loop has them (online/sim/scene_hardware.hpp, pi_parameters_with_hardware): the
  // controller follows its own force through the sensor's and the transport's delay; the scene's
  // PI parameters leave the removed feedthrough empty (the identity).
  s.hardware.feedthrough_delay =
      (e.force_sensor.present ? e.force_sensor.delay_samples : 0) + e.transport_delay_samples;
  if (e.actuator.present) {
    s.hardware.actuator_gain = e.actuator.gain;
    s.hardware.actuator_lag_s = e.actuator.lag_s;
  }
  if (e.force_sensor.present) s.hardware.sensor_gain_error = e.force_sensor.gain_error;
  return s;
}

}  // namespace

SampledLoop sampled_loop(const ScenePlant& p, double rate_hz,
                         const controller::design::PiGains& gains) {
  const auto& d = p.scene.discretisation;
  SampledLoop s = sampled_loop_frame(p, rate_hz);
  const plant::lti::DiscretisationOptions o{d.method, 1.0 / rate_hz, d.prewarp_hz, false};
  try {
    s.stability = controller::design::sampled_loop_stability(
        plant::lti::discretise(p.feedback_path, o), gains, s.hardware);
  } catch (const std::invalid_argument& ex) {
    throw common::InputError(p.scene.file, std::string("[discretisation]: the feedback path at ") +
                                               std::to_string(rate_hz) + " Hz: " + ex.what());
  }
  return s;
}

SampledLoop sampled_loop(const ScenePlant& p) {
  const auto& d = p.scene.discretisation;
  if (!p.state_space) return sampled_loop(p, d.rate_hz, p.gains);
  // The user's controller as the runtime runs it: it removes the discrete plant's own D22.
  SampledLoop s = sampled_loop_frame(p, d.rate_hz);
  try {
    const auto g22 =
        plant::lti::discretise(p.feedback_path, {d.method, 1.0 / d.rate_hz, d.prewarp_hz, false});
    s.hardware.removed_feedthrough = g22.sys.D;
    s.stability = controller::design::sampled_loop_stability(
        g22, p.state_space->discrete, s.hardware, state_space_reference_rad_s(p.scene));
  } catch (const std::invalid_argument& ex) {
    throw common::InputError(p.scene.file, std::string("[discretisation]: the sampled loop at ") +
                                               std::to_string(d.rate_hz) + " Hz: " + ex.what());
  }
  return s;
}

controller::design::SampledLoopModel sampled_loop_model(const ScenePlant& p) {
  const auto& d = p.scene.discretisation;
  SampledLoop s = sampled_loop_frame(p, d.rate_hz);
  try {
    const auto g22 =
        plant::lti::discretise(p.feedback_path, {d.method, 1.0 / d.rate_hz, d.prewarp_hz, false});
    if (p.state_space) s.hardware.removed_feedthrough = g22.sys.D;
    return controller::design::sampled_loop_model(
        g22,
        p.state_space ? p.state_space->discrete
                      : controller::design::pi_discrete_controller(p.gains, 1.0 / d.rate_hz),
        s.hardware);
  } catch (const std::invalid_argument& ex) {
    throw common::InputError(p.scene.file, std::string("[discretisation]: the sampled loop at ") +
                                               std::to_string(d.rate_hz) + " Hz: " + ex.what());
  }
}

SampledLoopRemedy stable_sampled_loop_remedy(const ScenePlant& p) {
  SampledLoopRemedy r;
  if (!has_pi_controller(p)) return r;  // the searches change the PI's rate and design
  const double rate = p.scene.discretisation.rate_hz;
  const auto stable_at = [&](double rate_hz, const controller::design::PiGains& g) {
    try {
      return sampled_loop(p, rate_hz, g).stability.stable();
    } catch (const common::InputError&) {
      return false;  // a discretisation refused at that rate is no remedy
    }
  };
  // Rates: 1, 2, 5, 10, 20, 50 ... Hz above the scene's (the gains do not depend on the rate).
  for (double decade = 1; decade <= kMaxSuggestedRateHz && !r.rate_hz; decade *= 10)
    for (const double m : {1.0, 2.0, 5.0}) {
      const double candidate = m * decade;
      if (candidate <= rate || candidate > kMaxSuggestedRateHz) continue;
      if (stable_at(candidate, p.gains)) {
        r.rate_hz = candidate;
        break;
      }
    }
  // omega_d at the scene's rate: both loops (the design changes the continuous one too).
  const auto stable_with = [&](double omega_d_hz) {
    const auto g = gains_at(p, omega_d_hz);
    return controller::design::loop_stability(p.feedback_path, g).stable() && stable_at(rate, g);
  };
  const double wd = p.scene.controller.omega_d_hz;
  double lo = wd / 2;
  while (lo > wd * 1e-4 && !stable_with(lo)) lo /= 2;
  if (lo <= wd * 1e-4) return r;
  // Stable at lo, unstable at hi: bisection to 1e-4 relative, then rounded down and checked.
  double hi = std::min(2 * lo, wd);
  while (hi - lo > 1e-4 * hi) {
    const double mid = 0.5 * (lo + hi);
    (stable_with(mid) ? lo : hi) = mid;
  }
  const double rounded = round_down_3(lo);
  r.omega_d_hz = stable_with(rounded) ? rounded : lo;
  return r;
}

void require_stable_loop(const ScenePlant& p) {
  // The plant first: a divergent passive mode grows in every run (sim runs the controller off too).
  if (!p.statics.stable())
    throw common::InputError(scene_place(p.scene, "scene", "model"),
                             "[scene]: model " + p.scene.model_path +
                                 (p.scene.gravity_preload ? " with the gravity preload: " : ": ") +
                                 plant::lti::to_string(p.statics) +
                                 "; a statically unstable plant is neither built nor run (flexloop "
                                 "analyse shows its modes)");
  const auto& c = p.scene.controller;
  if (!has_controller(p)) return;  // nothing closes a loop
  if (p.state_space) {
    if (!p.loop.stable()) {  // only a continuous controller has poles here
      char growth[200];
      std::snprintf(growth, sizeof growth,
                    "[controller]: the continuous closed loop with this controller is unstable: "
                    "%d poles in the right half plane, the fastest growing as e^(%.3g t)",
                    p.loop.unstable, p.loop.largest_real_part);
      throw common::InputError(c.file_place, growth);
    }
    require_stable_sampled_loop(p);
    return;
  }
  if (p.loop.stable()) {
    require_stable_sampled_loop(p);
    return;
  }
  char growth[160];
  std::snprintf(growth, sizeof growth,
                "the closed loop is unstable: %d poles in the right half plane, the fastest "
                "growing as e^(%.3g t) (%.3g Hz)",
                p.loop.unstable, p.loop.largest_real_part, p.loop.largest_real_part / kTwoPi);
  std::string what = std::string("[controller]: ") + growth;
  const auto leak = minimum_stable_leak_hz(p);
  if (leak && *leak > c.leak_hz) {
    // Rounded up at 3 significant digits: the bound itself is only marginally stable.
    const double step = std::pow(10.0, std::floor(std::log10(*leak)) - 2);
    char fix[200];
    std::snprintf(fix, sizeof fix, "; a leak_hz of at least %.3g makes it stable (it is %.3g): %s",
                  std::ceil(*leak / step) * step, c.leak_hz,
                  p.scene.gravity_preload
                      ? "the gravity preload's negative geometric stiffness needs the static "
                        "stiffness a leaky integrator gives back"
                      : "a leaky integrator gives the struts static stiffness back");
    what += fix;
  } else if (leak) {
    what += "; a smaller leak would be stable but this one is not: check omega_d_hz and zeta";
  } else {
    what += "; no leak up to omega_d stabilises it: change omega_d_hz or zeta";
  }
  throw common::InputError(c.place, what);
}

void require_stable_sampled_loop(const ScenePlant& p) {
  const SampledLoop s = sampled_loop(p);
  const auto& st = s.stability;
  if (st.stable()) return;
  const auto& d = p.scene.discretisation;
  // How fast: a disturbance doubles in T ln 2 / ln(rho).
  const double doubling_s = std::log(2.0) / std::log(st.spectral_radius) / s.rate_hz;
  char head[400];
  std::snprintf(
      head, sizeof head,
      "[discretisation]: the sampled loop is unstable at %g Hz (%s; the controller as it runs, "
      "the held command%s): spectral radius %.6g, %d pole%s outside the unit circle, "
      "a disturbance doubles every %.3g s%s",
      s.rate_hz, plant::lti::to_string(d.method).c_str(),
      delay_text(s.hardware.feedthrough_delay).c_str(), st.spectral_radius, st.unstable,
      st.unstable == 1 ? "" : "s", doubling_s,
      has_continuous_loop(p) ? ", although the continuous loop is stable" : "");
  std::string what = head;
  if (p.state_space)
    throw common::InputError(
        p.scene.controller.file_place,
        what +
            "; the controller file's design does not hold at this rate with the "
            "scene's hardware: redesign it for the loop as it runs (`flexloop "
            "build` writes the discrete plant it sees)");
  const SampledLoopRemedy r = stable_sampled_loop_remedy(p);
  char fix[400];
  if (r.rate_hz && r.omega_d_hz)
    std::snprintf(fix, sizeof fix,
                  "; stable: rate_hz = %g (the lowest of 1, 2, 5 x 10^k Hz), or omega_d_hz <= %g "
                  "(%s) at %g Hz",
                  *r.rate_hz, *r.omega_d_hz,
                  scene_place(p.scene, "controller", "omega_d_hz").c_str(), s.rate_hz);
  else if (r.rate_hz)
    std::snprintf(fix, sizeof fix,
                  "; stable: rate_hz = %g (the lowest of 1, 2, 5 x 10^k Hz); no omega_d_hz below "
                  "%g is stable at %g Hz",
                  *r.rate_hz, p.scene.controller.omega_d_hz, s.rate_hz);
  else if (r.omega_d_hz)
    std::snprintf(fix, sizeof fix,
                  "; stable: omega_d_hz <= %g (%s) at %g Hz; no rate up to %g Hz is", *r.omega_d_hz,
                  scene_place(p.scene, "controller", "omega_d_hz").c_str(), s.rate_hz,
                  kMaxSuggestedRateHz);
  else
    std::snprintf(fix, sizeof fix,
                  "; no rate up to %g Hz and no smaller omega_d_hz makes it stable: check the "
                  "[effects] (delays, actuator gain and lag, sensor gain error)",
                  kMaxSuggestedRateHz);
  throw common::InputError(scene_place(p.scene, "discretisation", "rate_hz"), what + fix);
}

plant::lti::StateSpace reduced_plant(const plant::lti::StateSpace& full, const Scene& scene) {
  const auto& r = scene.reduction;
  const auto fail = [&](const std::string& what) {
    throw common::InputError(r.place, "[plant]: reduction: " + what);
  };
  if (r.order > full.nx())
    fail("order " + std::to_string(r.order) + " is above the plant's " + std::to_string(full.nx()) +
         " states");
  // The floor's position and velocity as states (acceleration inputs): the loop starts them
  // where the floor is (online/sim/loop_hardware.hpp), so they must stay states with their
  // labels. Modal truncation keeps them as the coordinates of its block at the origin; balanced
  // coordinates mix them.
  std::vector<std::string> floor_states;
  for (const std::string& w : scene.disturbances)
    if (w.rfind("acc:", 0) == 0)
      for (const char* kind : {"pos:", "vel:"}) {
        const std::string label = kind + w.substr(4);
        if (std::find(full.states.begin(), full.states.end(), label) != full.states.end())
          floor_states.push_back(label);
      }
  try {
    if (r.method == "balanced") {
      if (!floor_states.empty())
        fail("this plant has the floor's position as states (" + floor_states.front() +
             ", ...), which balanced coordinates mix with the structure's; use modal or "
             "modal-dc");
      return plant::lti::balanced_truncation(full, r.order).sys;
    }
    const plant::lti::ReducedModel m =
        plant::lti::modal_truncation(full, {.order = r.order > 0 ? r.order : -1,
                                            .below_hz = r.below_hz,
                                            .dc_correction = r.method == "modal-dc",
                                            .band_low_hz = r.band_hz > 0 ? r.band_hz / 1e4 : 0,
                                            .band_hz = r.band_hz,
                                            .origin_states = floor_states});
    for (const std::string& label : floor_states)
      if (std::find(m.sys.states.begin(), m.sys.states.end(), label) == m.sys.states.end())
        fail("the floor's states (" + label +
             ", ...) do not span the plant's poles at the origin "
             "(a rigid-body mode of the structure itself?): they cannot be kept as states");
    return m.sys;
  } catch (const common::InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
  return full;  // not reached
}

SampledScene sample_scene(const ScenePlant& p) {
  const auto& d = p.scene.discretisation;
  const plant::lti::DiscretisationOptions o{d.method, 1.0 / d.rate_hz, d.prewarp_hz, false};
  try {
    if (!has_controller(p)) return {plant::lti::discretise(p.plant, o), {}, {}};
    SampledScene s{
        plant::lti::discretise(p.plant, o),
        p.state_space ? p.state_space->discrete : plant::lti::discretise(p.controller, o),
        {}};
    s.closed_loop = plant::lti::close_loop_sampled(s.plant, s.controller, p.partition);
    return s;
  } catch (const std::invalid_argument& e) {
    throw common::InputError(p.scene.file, std::string("[discretisation]: ") + e.what());
  }
}

}  // namespace flexloop::scene
