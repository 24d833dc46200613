// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The local engine (`flexloop campaign submit --engine local`, and `flexloop campaign` itself):
// the shards of a plan run as child processes of this machine, `jobs` at a time, each the same
// `flexloop campaign run plan.json --shard K/M -o DIR/shard-K.jsonl` a Slurm array element runs
// (so a shard computes the same bytes whichever engine starts it). Progress with an estimate of
// the time left on stderr, redrawn at most four times a second (a line every ten seconds when
// stderr is not a terminal), counted from the shard files' complete lines.
#include <string>
#include <vector>

namespace flexloop::campaign {

struct LocalEngineOptions {
  std::string program;  ///< the flexloop executable the children run
  std::string plan_path;
  long evaluations = 0;  ///< the plan's, for the progress
  int shards = 1;
  int jobs = 1;          ///< children at once
  std::string work_dir;  ///< where shard-K.jsonl go
  bool quiet = false;
};

/// Runs every shard (a shard file already complete costs its reading only) and returns the
/// shard files in shard order. @throws std::runtime_error naming each shard whose child failed
/// (its exit status; the child's own message went to stderr).
std::vector<std::string> run_local(const LocalEngineOptions& o);

/// "[#######.............]  35 % 3500/10000  412.0/s  ~16 s left": the rate and the time left
/// from the samples of this run (done - done_before, a rerun finds some done already).
std::string progress_text(long done, long total, double elapsed_s, long done_before = 0);

}  // namespace flexloop::campaign
