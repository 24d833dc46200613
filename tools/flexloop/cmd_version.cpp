// SPDX-License-Identifier: BSD-3-Clause
// `flexloop version`: what was built, from which commit, with which compiler and libraries.
#include <dlfcn.h>
#include <lcm/lcm.h>
#include <Eigen/Core>
#include <cstdio>

#include "common/build_info.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

namespace {

// The BLAS this process runs and its threads (tools/flexloop/blas_threads.hpp).
void print_blas() {
  using GetInt = int (*)();
  using GetText = char* (*)();
  const auto threads = reinterpret_cast<GetInt>(::dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto core = reinterpret_cast<GetText>(::dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  if (!threads) {
    std::printf("blas     not OpenBLAS (its own threading)\n");
    return;
  }
  std::printf("blas     OpenBLAS, %s kernel, %d thread%s\n", core ? core() : "?", threads(),
              threads() == 1 ? "" : "s");
}

}  // namespace

void register_version(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("version", "Print version, git hash, compiler, Eigen and LCM versions");
  cmd->footer("Example:\n  flexloop version");
  cmd->callback([] {
    std::printf("flexloop %s\n", common::build_info::kVersion);
    std::printf("git      %s\n", common::build_info::kGitHash);
    std::printf("compiler %s (%s build)\n", common::build_info::kCompiler,
                common::build_info::kBuildType);
    std::printf("eigen    %d.%d.%d\n", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION,
                EIGEN_MINOR_VERSION);
    std::printf("lcm      %d.%d.%d\n", LCM_MAJOR_VERSION, LCM_MINOR_VERSION, LCM_MICRO_VERSION);
    print_blas();
  });
}

}  // namespace flexloop::cli
