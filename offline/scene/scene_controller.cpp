// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/scene_controller.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "common/json_document.hpp"
#include "plant/lti/state_space_json.hpp"

namespace flexloop::scene {

namespace {

std::string hz(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9g Hz", v);
  return text;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// For each of the scene's channels (in the scene's order) its index among the file's labels.
std::vector<Eigen::Index> order_of(const std::vector<std::string>& file_labels,
                                   const std::vector<std::string>& scene_channels,
                                   const std::string& place, const char* key, const char* kind) {
  for (const auto& l : file_labels)
    if (std::find(scene_channels.begin(), scene_channels.end(), l) == scene_channels.end())
      throw common::InputError(place, std::string("key '") + key + "': '" + l +
                                          "' is not one of the scene's " + kind + " (" +
                                          joined(scene_channels) + ")");
  std::vector<Eigen::Index> index;
  for (const auto& c : scene_channels) {
    const auto it = std::find(file_labels.begin(), file_labels.end(), c);
    if (it == file_labels.end())
      throw common::InputError(place, std::string("key '") + key + "': the scene's " + kind + " '" +
                                          c + "' is missing (the controller must take every one)");
    index.push_back(it - file_labels.begin());
  }
  return index;
}

// The system with inputs and outputs in the scene's order (sensors in, actuators out).
plant::lti::StateSpace in_scene_order(const plant::lti::StateSpace& c, const Scene& scene,
                                      const std::string& place) {
  const auto in = order_of(c.inputs, scene.sensors, place, "inputs", "sensors");
  const auto out = order_of(c.outputs, scene.actuators, place, "outputs", "actuators");
  plant::lti::StateSpace s = c;
  s.inputs = scene.sensors;
  s.outputs = scene.actuators;
  for (std::size_t j = 0; j < in.size(); ++j) {
    s.B.col(static_cast<Eigen::Index>(j)) = c.B.col(in[j]);
    for (std::size_t i = 0; i < out.size(); ++i)
      s.D(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = c.D(out[i], in[j]);
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    s.C.row(static_cast<Eigen::Index>(i)) = c.C.row(out[i]);
  return s;
}

}  // namespace

SceneController load_scene_controller(const Scene& scene) {
  const auto& c = scene.controller;
  const std::string& file = c.file;
  const nlohmann::json j = common::parse_json_file(file);
  SceneController out;
  const auto& d = scene.discretisation;
  const double dt = 1.0 / d.rate_hz;
  if (j.is_object() && j.contains("dt")) {
    plant::lti::DiscreteStateSpace ds = plant::lti::discrete_from_json(j, file).sys;
    if (std::abs(ds.dt * d.rate_hz - 1) > 1e-9)
      throw common::InputError(
          file, "key 'dt': the controller is designed for " + hz(1 / ds.dt) +
                    ", the scene runs at " + hz(d.rate_hz) + " (" + c.file_place +
                    "): design it at the scene's rate, or give it in continuous time "
                    "and flexloop discretises it");
    ds.sys = in_scene_order(ds.sys, scene, file);
    ds.dt = dt;
    out.discrete = ds;
  } else {
    const plant::lti::StateSpace cs =
        in_scene_order(plant::lti::continuous_from_json(j, file).sys, scene, file);
    out.continuous = cs;
    try {
      out.discrete = plant::lti::discretise(cs, {d.method, dt, d.prewarp_hz, false});
    } catch (const std::invalid_argument& e) {
      throw common::InputError(
          file, std::string("the controller is not discretised at the scene's rate: ") + e.what());
    }
  }
  return out;
}

}  // namespace flexloop::scene
