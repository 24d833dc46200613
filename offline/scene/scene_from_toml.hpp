// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The scene reader's second half: a scene from its TOML document (what parse_scene reads after
// the text became a table). A campaign sets drawn values in a scene's document and reads it here,
// through every check a user's file passes, without writing and parsing the text again
// (offline/campaign/parameter_paths.hpp). `file` places relative paths (the model, a controller
// file) and names the errors, as in parse_scene.
#include <toml++/toml.h>

#include <string>

#include "offline/scene/scene.hpp"

namespace flexloop::scene {

Scene scene_from_toml(const toml::table& root, const std::string& file);

}  // namespace flexloop::scene
