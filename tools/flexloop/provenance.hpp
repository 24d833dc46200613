#pragma once
// Provenance recorded in every artefact a subcommand writes: the input file, its SHA-256, and
// the flexloop version and commit that produced the artefact.
#include <nlohmann/json.hpp>
#include <string>

namespace flexloop::cli {

/// SHA-256 of a file as lowercase hex (OpenSSL EVP). Throws flexloop::InputError if unreadable.
std::string file_sha256(const std::string& path);

/// {"source": path, "source_sha256": ..., "flexloop_version": ..., "flexloop_git": ..., "command":
/// ...}
nlohmann::json make_provenance(const std::string& source_path, const std::string& command);

}  // namespace flexloop::cli
