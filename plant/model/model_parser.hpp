// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Reads a model file (TOML; format in doc/model_format.md) into a Model, with the
// coordinate partition resolved and the undeformed configuration computed.
// Bad input throws flexloop::InputError with "file:line" and what is wrong.
#include <string>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

Model load_model(const std::string& path);
Model parse_model(const std::string& toml_text, const std::string& file_name);

/// Marks rigid deformations whose coordinates are all fixed as inert (identities, not equations);
/// called again whenever the partition changes.
void mark_inert_deformations(Model& m);

}  // namespace flexloop::plant::model
