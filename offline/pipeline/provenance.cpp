// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/provenance.hpp"

#include "common/build_info.hpp"
#include "common/sha256.hpp"
#include "offline/scene/loop_input.hpp"

namespace flexloop::pipeline {

nlohmann::json make_provenance(const std::string& source_path, const std::string& command) {
  return {{"source", source_path},
          {"source_sha256", common::file_sha256(source_path)},
          {"flexloop_version", common::build_info::kVersion},
          {"flexloop_git", common::build_info::kGitHash},
          {"command", command}};
}

}  // namespace flexloop::pipeline
