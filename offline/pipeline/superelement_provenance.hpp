// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What an artefact records of a model's superelements (issue 58): the FE files it was reduced
// from (path, bytes, modification time: their SHA-256 would read a gigabyte of text again at
// 10^6 DOFs) and the reduction (cut-off, modes kept, the FE model's size).
#include <nlohmann/json.hpp>

#include "plant/model/model.hpp"

namespace flexloop::pipeline {

/// [{"id", "full_dofs", "interface_dofs", "modes_up_to_hz", "modes_kept",
///   "fixed_interface_hz": [lowest, highest], "files": [{"path", "bytes", "modified"}]}, ...];
/// null when the model has none.
nlohmann::json superelement_provenance(const plant::model::Model& m);

}  // namespace flexloop::pipeline
