#pragma once
// Reads a model file (TOML; format in README.md "Model files") into a Model, with the
// coordinate partition resolved and the undeformed configuration computed.
// Bad input throws flexloop::InputError with "file:line" and what is wrong.
#include <string>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

Model load_model(const std::string& path);
Model parse_model(const std::string& toml_text, const std::string& file_name);

}  // namespace flexloop::plant::model
