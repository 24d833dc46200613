// `flexloop version`: what was built, from which commit, with which compiler and libraries.
#include <lcm/lcm.h>
#include <Eigen/Core>
#include <cstdio>

#include "common/build_info.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

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
  });
}

}  // namespace flexloop::cli
