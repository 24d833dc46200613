// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Version, git hash and compiler of this build, for `flexloop version` and the provenance that
// artefacts, reports and FMUs carry. Defined in a file the build writes at configure time
// (cmake/BuildInfo.cmake, library flexloop_build_info), so that a new commit or a dirty tree
// recompiles that one file and not the code that reads these.
namespace flexloop::common::build_info {
extern const char* const kVersion;
extern const char* const kGitHash;   // short hash, "-dirty" when tracked files were changed
extern const char* const kCompiler;  // "GNU 12.2.0"
extern const char* const kBuildType;
}  // namespace flexloop::common::build_info
