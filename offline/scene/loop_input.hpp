// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the loop commands (sim, plant, controller, hil) run: a loop artefact, read from an
// artefact file, or built from a scene file by the offline pipeline (the scene's loop must be
// stable) exactly as `flexloop build` writes it.
#include <string>

#include "artefact/loop_artefact.hpp"

namespace flexloop::scene {

using LoopInputOptions = artefact::LoopOverrides;

/// @throws flexloop::InputError naming the file: a bad scene, artefact or an override that an
/// artefact cannot take (its rate and form are fixed: rebuild it).
artefact::LoopArtefact load_loop(const std::string& path, const LoopInputOptions& o = {});

/// Provenance of an artefact built from `scene_path` (its model, both SHA-256, this build).
artefact::Provenance loop_provenance(const std::string& scene_path, const std::string& model_path);

}  // namespace flexloop::scene
