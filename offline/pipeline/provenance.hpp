// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Provenance recorded in every artefact a subcommand writes: the input file, its SHA-256, and
// the flexloop version and commit that produced the artefact.
#include <nlohmann/json.hpp>
#include <string>

namespace flexloop::pipeline {

/// {"source": path, "source_sha256": ..., "flexloop_version": ..., "flexloop_git": ..., "command":
/// ...}
nlohmann::json make_provenance(const std::string& source_path, const std::string& command);

}  // namespace flexloop::pipeline
