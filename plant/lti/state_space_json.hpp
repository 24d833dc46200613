// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// JSON artefacts for continuous and discrete state-space systems.
//
// Continuous:  {"states": [..], "inputs": [..], "outputs": [..],
//               "A": [[..], ..], "B": .., "C": .., "D": .., "provenance": {..} (optional)}
// Discrete:    {"method": "zoh", "dt": 0.001, "prewarp_hz": 0, "spectral_radius": 0.99,
//               "states", "inputs", "outputs", "Ad", "Bd", "Cd", "Dd", "provenance": {..}}
// Matrices are lists of rows. The label counts fix the sizes (nx states, nu inputs, ny outputs),
// so an empty dimension (a 0 x nu B, say) is still well defined: A, B, C, D are nx x nx, nx x nu,
// ny x nx, ny x nu. Doubles are written in shortest round-trip form, so write + read is bit-exact.
// "provenance" is an object the caller supplies (source file, its hash, flexloop version, ...)
// and is passed through unchanged. For "foh" and "backward-euler" the discrete state is shifted
// (see plant/lti/discretise.hpp).
//
// Reading reports bad input as flexloop::InputError with the place, e.g.
// "plant.json: key 'A' row 3: has 2 entries, expected 4 (one per state)"; rows and columns are
// counted from 1. Files are written atomically: a temporary file in the same directory, flushed
// to disk, then renamed over the target, so a crash never leaves a half-written artefact.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "common/json_document.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

struct ContinuousArtefact {
  StateSpace sys;
  nlohmann::json provenance;  ///< null when the file has none
};

struct DiscreteArtefact {
  DiscreteStateSpace sys;
  nlohmann::json provenance;  ///< null when the file has none
};

/// Throws std::invalid_argument when the system does not validate (e.g. a non-finite entry,
/// which JSON cannot represent).
nlohmann::json to_json(const StateSpace& sys, const nlohmann::json& provenance = nullptr);
using common::matrix_to_json;  // common/json_document.hpp: a matrix as a list of rows
nlohmann::json to_json(const DiscreteStateSpace& sys, const nlohmann::json& provenance = nullptr);

/// `source` names the document in error places (usually the file name).
ContinuousArtefact continuous_from_json(const nlohmann::json& j, const std::string& source);
DiscreteArtefact discrete_from_json(const nlohmann::json& j, const std::string& source);

/// Read and validate a file; InputError for unreadable files, invalid JSON and bad content.
ContinuousArtefact read_continuous(const std::filesystem::path& file);
DiscreteArtefact read_discrete(const std::filesystem::path& file);

void write_continuous(const std::filesystem::path& file, const StateSpace& sys,
                      const nlohmann::json& provenance = nullptr);
void write_discrete(const std::filesystem::path& file, const DiscreteStateSpace& sys,
                    const nlohmann::json& provenance = nullptr);

/// Readable layout (one matrix row per line, known keys first) written atomically; throws
/// std::runtime_error when the directory is not writable or the disk is full.
void write_json_atomically(const std::filesystem::path& file, const nlohmann::json& j);

}  // namespace flexloop::plant::lti
