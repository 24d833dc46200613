// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/scene_fmu.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "artefact/fmu_parameters.hpp"

namespace flexloop::scene {

namespace {

bool among(const std::vector<std::string>& names, const std::string& n) {
  return std::find(names.begin(), names.end(), n) != names.end();
}

}  // namespace

void read_fmu_controller(const common::TomlReader& cr, const toml::table& t,
                         const std::filesystem::path& base, Scene& s) {
  auto& c = s.controller;
  cr.allow_only({"enabled", "type", "file", "parameters", "map", "fmu_max_unpacked_mb"});
  const std::string file = cr.string("file");
  // Absolute: the artefact names the FMU wherever it is read from.
  const std::filesystem::path given(file);
  c.file = std::filesystem::absolute(given.is_absolute() ? given : base / given)
               .lexically_normal()
               .string();
  if (!std::filesystem::is_regular_file(c.file))
    cr.fail("FMU file '" + c.file + "' does not exist", cr.get("file"));
  c.file_place = cr.place(cr.get("file"));
  c.place = c.file_place;
  if (const auto* n = t.get("fmu_max_unpacked_mb")) {
    const auto* mb = n->as_integer();
    if (!mb || mb->get() < 1 || mb->get() > artefact::kMaxFmuUnpackedMb)
      cr.fail("'fmu_max_unpacked_mb' must be a whole number of MB, 1 .. " +
                  std::to_string(artefact::kMaxFmuUnpackedMb),
              n);
    c.fmu_max_unpacked_mb = static_cast<long>(mb->get());
  }
  if (const auto* n = t.get("parameters")) {
    const auto* p = n->as_table();
    if (!p) cr.fail("'parameters' must be a table of name = number", n);
    for (const auto& [name, value] : *p) {
      const auto v = value.value<double>();
      if (!v || !std::isfinite(*v))
        cr.fail("parameter '" + std::string(name.str()) + "' must be a finite number", &value);
      c.fmu_parameters.emplace_back(std::string(name.str()), *v);
    }
  }
  if (const auto* n = t.get("map")) {
    const auto* m = n->as_table();
    if (!m) cr.fail("'map' must be a table of scene channel = FMU variable", n);
    // A sensor's or an actuator's variable; `kind` narrows a name that is both.
    const auto entry = [&](const std::string& key, const toml::node& variable, const char* kind) {
      const bool sensor = among(s.sensors, key), actuator = among(s.actuators, key);
      const bool to_sensor = kind ? kind[0] == 's' && sensor : sensor,
                 to_actuator = kind ? kind[0] == 'a' && actuator : actuator;
      if (!to_sensor && !to_actuator)
        cr.fail("map: '" + key + "' is not one of the scene's " +
                    (kind ? std::string(kind) : "sensors or actuators"),
                &variable);
      if (!kind && sensor && actuator)
        cr.fail("map: '" + key +
                    "' is both a sensor and an actuator: name it under [controller.map.sensors] "
                    "or [controller.map.actuators]",
                &variable);
      const auto v = variable.value<std::string>();
      if (!v || v->empty()) cr.fail("map: '" + key + "' must name an FMU variable", &variable);
      (to_sensor ? c.fmu_sensor_map : c.fmu_actuator_map).emplace_back(key, *v);
    };
    for (const auto& [k, value] : *m) {
      const std::string key(k.str());
      if (key == "sensors" || key == "actuators") {
        const auto* sub = value.as_table();
        if (!sub) cr.fail("map: '" + key + "' must be a table of channel = FMU variable", &value);
        for (const auto& [channel, variable] : *sub)
          entry(std::string(channel.str()), variable, key == "sensors" ? "sensors" : "actuators");
      } else {
        entry(key, value, nullptr);
      }
    }
  }
}

}  // namespace flexloop::scene
