#include "tools/scene/scene_plant.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/input_error.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/model/static_equilibrium.hpp"

namespace flexloop::scene {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

ScenePlant build_scene_plant(const Scene& scene, const ScenePlantOptions& options) {
  namespace model = plant::model;
  ScenePlant p;
  p.scene = scene;
  p.model = model::load_model(scene.model_path);
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
  const Eigen::MatrixXd Kdd = p.lin.K.topLeftCorner(nd, nd);
  p.natural_frequencies_hz =
      plant::lti::natural_modes(Mdd, (p.lin.K + p.lin.N + p.lin.G).topLeftCorner(nd, nd))
          .frequencies_hz;

  try {
    p.plant = plant::lti::build_state_space(m, p.lin, concat(scene.disturbances, scene.actuators),
                                            concat(scene.performance, scene.sensors));
  } catch (const InputError& e) {
    throw InputError(scene.file, std::string("[plant]: ") + e.what());
  }
  p.partition = {static_cast<Eigen::Index>(scene.disturbances.size()),
                 static_cast<Eigen::Index>(scene.performance.size())};

  // The design uses the passive stiffness Kdd (the seed's formula); the actuated struts must be
  // the dynamic coordinates for it to mean what it says.
  if (static_cast<int>(scene.actuators.size()) != nd)
    throw InputError(scene.file,
                     "[plant]: PI force feedback needs one actuator per dynamic "
                     "coordinate (" +
                         std::to_string(nd) + "), got " + std::to_string(scene.actuators.size()));
  const auto& c = scene.controller;
  p.gains = controller::design::design_pi_force_feedback(
      Mdd, Kdd, {kTwoPi * c.omega_d_hz, c.zeta, kTwoPi * c.leak_hz});
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

void require_stable_loop(const ScenePlant& p) {
  const auto& c = p.scene.controller;
  if (p.loop.stable()) return;
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
  throw InputError(c.place, what);
}

SampledScene sample_scene(const ScenePlant& p) {
  const auto& d = p.scene.discretisation;
  const plant::lti::DiscretisationOptions o{d.method, 1.0 / d.rate_hz, d.prewarp_hz, false};
  try {
    SampledScene s{plant::lti::discretise(p.plant, o), plant::lti::discretise(p.controller, o), {}};
    s.closed_loop = plant::lti::close_loop_sampled(s.plant, s.controller, p.partition);
    return s;
  } catch (const std::invalid_argument& e) {
    throw InputError(p.scene.file, std::string("[discretisation]: ") + e.what());
  }
}

}  // namespace flexloop::scene
