#pragma once
// TEMPORARY (campaign-core's branch): the declarations of CAMPAIGN.md, so that this branch
// compiles before campaign-slurm's slurm_engine.* is merged. The lead takes theirs.
#include <string>
#include <vector>

namespace flexloop::campaign {

struct SlurmOptions {
  std::string partition, account;
  int shards = 1;
  int array_throttle = 0;
  std::string flexloop_program;
  std::string work_dir;
  double time_limit_min = 60;
};
std::vector<std::string> submit_slurm(const std::string& plan_path, const SlurmOptions& o);

}  // namespace flexloop::campaign
