// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A scene's controller FMU ([controller] type = "fmu", issue 33):
//
//   [controller]
//   type = "fmu"
//   file = "my_controller.fmu"        # relative to the scene file
//   fmu_max_unpacked_mb = 2048        # optional: the cap on the unpacked archive (default 1024)
//   [controller.parameters]           # optional: the FMU's real parameters, name = value
//   K_P_1_1 = 23.0
//   [controller.map]                  # optional: scene channel = FMU variable (default: same name)
//   "acc:x.3" = "a1"
//   [controller.map.sensors]          # for a name that is both a sensor and an actuator
//   "stress:e1.4" = "y1"
//   [controller.map.actuators]
//   "stress:e1.4" = "u1"
//
// The FMU's real inputs are the scene's sensors and its real outputs the actuators. The scene only
// reads the names; the FMU itself is opened when the loop starts (controller/fmu).
#include <toml++/toml.h>

#include "common/toml_reader.hpp"
#include "offline/scene/scene.hpp"

namespace flexloop::scene {

/// Reads the fmu keys of `cr` (the [controller] table `t`) into s.controller, checking the map's
/// channels against s.sensors and s.actuators (read before). @throws flexloop::InputError
/// "file:line: [controller]: ..." for a missing file, a non-number parameter, a map entry whose
/// key is not a sensor or actuator or whose value is not a name, a cap that is not 1 .. 2^20 MB.
void read_fmu_controller(const common::TomlReader& cr, const toml::table& t,
                         const std::filesystem::path& base, Scene& s);

}  // namespace flexloop::scene
