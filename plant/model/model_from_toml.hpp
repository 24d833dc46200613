// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The model reader's second half: a model from its TOML document (what parse_model reads after
// the text became a table). A campaign sets drawn values in a model's document and reads it here,
// through every check a user's file passes, without writing and parsing the text again
// (offline/campaign/parameter_paths.hpp). Bad input throws flexloop::InputError as parse_model
// does ("file:line" where the entry has a line).
#include <toml++/toml.h>

#include <string>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

Model model_from_toml(const toml::table& root, const std::string& file_name);

}  // namespace flexloop::plant::model
