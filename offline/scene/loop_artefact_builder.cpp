// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/loop_artefact_builder.hpp"

#include "offline/scene/loop_start_builder.hpp"

#include <cmath>

#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/pi_parameters.hpp"
#include "offline/scene/schema_conversion.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/lti/vibration_criterion.hpp"

namespace flexloop::scene {

static_assert(plant::lti::kFloorFilterOrder == artefact::kFloorFilterOrder,
              "the floor filter the offline design makes is the one the artefact carries");

std::string channel_unit(const std::string& channel) {
  const auto colon = channel.find(':');
  const std::string kind = channel.substr(0, colon), target = channel.substr(colon + 1);
  // Rotations: planar angles and Euler parameters; a deformation other than e1 (an elongation)
  // is a torsion or bending angle, its stress a moment.
  const bool rotation =
      target.rfind("phi.", 0) == 0 ||
      (target.size() > 1 && target[0] == 'l' && target[1] >= '0' && target[1] <= '3') ||
      (target[0] == 'e' && target.rfind("e1.", 0) != 0);
  if (kind == "acc") return rotation ? "rad/s^2" : "m/s^2";
  if (kind == "vel") return rotation ? "rad/s" : "m/s";
  if (kind == "pos") return rotation ? "rad" : "m";
  return rotation ? "N m" : "N";  // force, stress, reaction
}

namespace {

// The sensor's and the transport's delay, which the controller follows its own force through.
int feedthrough_delay(const Scene& sc) {
  const auto& e = sc.effects;
  return (e.force_sensor.present ? e.force_sensor.delay_samples : 0) + e.transport_delay_samples;
}

// The command limit [N] the actuator and [controller] force_limit_n set (infinite: none).
double command_limit(const Scene& sc) {
  const auto& e = sc.effects;
  const double limit = sc.controller.force_limit_n;
  return e.actuator.present ? std::min(limit, e.actuator.force_limit_n / std::abs(e.actuator.gain))
                            : limit;
}

}  // namespace

artefact::PiParameters pi_parameters_with_hardware(const ScenePlant& p, double dt) {
  artefact::PiParameters pi = pi_parameters(p, dt);
  pi.feedthrough_delay = feedthrough_delay(p.scene);
  if (p.scene.effects.actuator.present) {
    const double limit = command_limit(p.scene);
    pi.u_min = Eigen::VectorXd::Constant(1, -limit);
    pi.u_max = Eigen::VectorXd::Constant(1, limit);
  }
  return pi;
}

artefact::StateSpaceParameters state_space_parameters_with_hardware(const ScenePlant& p,
                                                                    const SampledScene& sampled) {
  artefact::StateSpaceParameters c;
  const auto& d = p.state_space->discrete.sys;
  c.A = d.A;
  c.B = d.B;
  c.C = d.C;
  c.D = d.D;
  c.dt = p.state_space->discrete.dt;
  const double limit = command_limit(p.scene);
  if (std::isfinite(limit)) {
    c.u_min = Eigen::VectorXd::Constant(1, -limit);
    c.u_max = Eigen::VectorXd::Constant(1, limit);
  }
  // The discrete plant's own feedthrough from the actuators to the sensors.
  const auto& D = sampled.plant.sys.D;
  c.feedthrough = D.bottomRightCorner(static_cast<Eigen::Index>(p.scene.sensors.size()),
                                      static_cast<Eigen::Index>(p.scene.actuators.size()));
  c.feedthrough_delay = feedthrough_delay(p.scene);
  c.anti_windup = artefact::parse_anti_windup(p.scene.controller.anti_windup);
  return c;
}

artefact::FmuParameters fmu_parameters(const Scene& sc) {
  const auto& c = sc.controller;
  artefact::FmuParameters f;
  f.file = c.file;
  f.sha256 = common::file_sha256(c.file);
  f.parameters = c.fmu_parameters;
  f.max_unpacked_mb = c.fmu_max_unpacked_mb;
  // Each channel's FMU variable: its own name unless the map says otherwise.
  const auto variable = [](const auto& map, const std::string& channel) {
    for (const auto& [from, to] : map)
      if (from == channel) return to;
    return channel;
  };
  for (const auto& s : sc.sensors) f.inputs.push_back(variable(c.fmu_sensor_map, s));
  for (const auto& u : sc.actuators) f.outputs.push_back(variable(c.fmu_actuator_map, u));
  return f;
}

artefact::LoopArtefact loop_artefact_without_start(const ScenePlant& p, const SampledScene& sampled,
                                                   artefact::PlantForm form,
                                                   const artefact::Provenance& provenance) {
  const Scene& sc = p.scene;
  artefact::LoopArtefact a;
  a.name = sc.name;
  a.source = sc.file;
  a.provenance = provenance;
  a.rate_hz = sc.discretisation.rate_hz;
  a.method = sampled.plant.method;
  a.prewarp_hz = sampled.plant.prewarp_hz;
  const auto map = [](const std::vector<std::string>& names) {
    std::vector<artefact::Channel> out;
    for (const auto& n : names) out.push_back({n, channel_unit(n)});
    return out;
  };
  a.channels = {map(sc.disturbances), map(sc.actuators), map(sc.performance), map(sc.sensors)};
  const auto& d = sampled.plant.sys;
  a.plant.form = form;
  a.plant.A = d.A;
  a.plant.B = d.B;
  a.plant.C = d.C;
  a.plant.D = d.D;
  a.plant.states = d.states;
  a.plant.spectral_radius = sampled.plant.spectral_radius;
  if (form == artefact::PlantForm::kModal) {
    try {
      const auto m = plant::lti::to_modal_form(sampled.plant);
      a.plant.modal = {m.Lambda_minus_I, m.B, m.C, m.D, m.T};
    } catch (const std::invalid_argument& e) {
      throw common::InputError(
          sc.file, std::string("the modal form is refused: ") + e.what() + " (use the dense form)");
    }
  }
  if (p.state_space) {
    a.controller = artefact::ControllerKind::kStateSpace;
    a.state_space = state_space_parameters_with_hardware(p, sampled);
  } else if (has_controller(p)) {
    a.controller = artefact::ControllerKind::kPiForceFeedback;
    a.pi = pi_parameters_with_hardware(p, a.dt());
  } else if (has_fmu_controller(p)) {
    a.controller = artefact::ControllerKind::kFmu;
    a.fmu = fmu_parameters(sc);
  }
  a.floor = sc.floor;
  if (sc.floor.spectrum != artefact::FloorSpectrum::kWhite) {
    const auto continuous = plant::lti::design_floor_filter(
        plant::lti::criterion_band_velocity_rms(vibration_criterion(sc.floor.spectrum)));
    const auto filter = plant::lti::discretise_floor_filter(continuous, a.dt());
    a.floor_filter = {filter.sys.A, filter.sys.B, filter.sys.C, filter.sys.D,
                      plant::lti::floor_motion_outputs(continuous)};
  }
  a.effects = sc.effects;
  a.duration_s = sc.run.duration_s;
  artefact::validate(a);
  return a;
}

artefact::LoopArtefact build_loop_artefact(const ScenePlant& p, const SampledScene& sampled,
                                           artefact::PlantForm form,
                                           const artefact::Provenance& provenance) {
  artefact::LoopArtefact a = loop_artefact_without_start(p, sampled, form, provenance);
  a.start = stationary_loop_start(a);
  return a;
}

}  // namespace flexloop::scene
