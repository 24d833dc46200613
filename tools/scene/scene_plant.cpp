#include "tools/scene/scene_plant.hpp"

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
  return p;
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
