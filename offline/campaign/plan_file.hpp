// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// plan.json (doc/campaign.md "plan.json"): what a campaign computes, fixed before any sample
// runs, so that sample i depends only on the plan and i. Its plan_id is the SHA-256 of its
// canonical content (every field but plan_id, nlohmann's compact dump with sorted keys): every
// shard line carries it, and `run` and `report` refuse what belongs to another plan.
#include <string>

#include <nlohmann/json.hpp>

namespace flexloop::campaign {

inline constexpr const char* kPlanFormat = "flexloop-campaign-plan";
inline constexpr int kPlanVersion = 1;

/// SHA-256 (hex) of the plan without its plan_id.
std::string plan_id_of(const nlohmann::json& plan);

/// The plan with its plan_id set.
nlohmann::json with_plan_id(nlohmann::json plan);

/// Reads a plan file. @throws flexloop::InputError naming the file when it is not a plan of this
/// format and version, or its plan_id is not that of its content (an edited plan).
nlohmann::json read_plan(const std::string& path);

/// The nominal loop artefact as `flexloop build` makes it from the scene, by its JSON's SHA-256:
/// it changes with any file the scene reads and with the build that makes it.
std::string nominal_artefact_sha256(const std::string& scene_path);

/// @throws flexloop::InputError when the scene, its model, the uncertain parameters file or the
/// controller file changed since the plan was made (their SHA-256 differ), or the nominal loop
/// artefact this build makes is not the plan's (another flexloop, or a change the hashes of the
/// files do not see): a sample would not be the plan's. Both hashes are named.
void require_plan_inputs_unchanged(const nlohmann::json& plan, const std::string& plan_path);

/// What every shard line says of the program that computed it: {"version", "build"}, the build
/// being the SHA-256 of the running executable (16 hex digits): two builds of one commit differ.
/// In the Python module (doc/python.md) it is the module's file, not python3's.
nlohmann::json line_build();

}  // namespace flexloop::campaign
