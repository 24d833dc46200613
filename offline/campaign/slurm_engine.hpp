#pragma once
// The Slurm engine of `campaign submit --engine slurm`: one array job whose element K runs shard K
// of the plan through the flexloop program's `campaign run` (doc/campaign_slurm.md).
//
// Slurm is driven through its own client programs (sbatch, squeue, scontrol, sacct on PATH, with
// the caller's environment: SLURM_CONF and the rest), each run with an argument vector, never
// through a shell. The job is followed with `squeue -r -t all` until every element has ended; the
// elements' final states and exit codes come from `scontrol show job` (Slurm keeps ended jobs
// there for MinJobAge seconds) or, when the controller has forgotten them, from `sacct`.
#include <string>
#include <vector>

namespace flexloop::campaign {

struct SlurmOptions {
  std::string partition, account;  // empty: the cluster's defaults
  int shards = 1;
  int array_throttle = 0;        // %N on --array; 0: none
  std::string flexloop_program;  // absolute path of the flexloop executable to run
  std::string work_dir;          // where the script, the shard files and Slurm's logs go
  double time_limit_min = 60;
};

/// Writes work_dir/campaign.sbatch: an array 0..shards-1 whose element K runs
/// `<flexloop> campaign run <plan> --shard K/<shards> -o <work_dir>/shard-K.jsonl`;
/// submits it (sbatch --parsable), waits (squeue, then scontrol or sacct) with progress on
/// stderr, and returns the shard files in shard order. Options that Slurm could not take (a
/// partition name with a blank, a work_dir with '%' or '"', shards < 1, a relative program path)
/// are common::InputError; a failed element (FAILED, TIMEOUT, CANCELLED, NODE_FAIL,
/// OUT_OF_MEMORY, ... or a non-zero exit code) is a std::runtime_error naming every failed
/// element, its state and exit code, and the last lines of its log. `campaign run` is idempotent:
/// calling this again after a failure completes the shards that are missing samples.
std::vector<std::string> submit_slurm(const std::string& plan_path, const SlurmOptions& o);

// The parts of submit_slurm, for the tests and for a user who submits the script by hand.

/// work_dir/shard-K.jsonl
std::string slurm_shard_file(const SlurmOptions& o, int shard);
/// Slurm's logs of element `shard` of job `job_id`: work_dir/campaign-<job>_<K>.out and .err.
std::string slurm_log_file(const SlurmOptions& o, const std::string& job_id, int shard,
                           const std::string& extension);

/// The text of campaign.sbatch for an absolute plan path (options checked as submit_slurm does).
std::string sbatch_script(const std::string& plan_path, const SlurmOptions& o);

/// One array element as Slurm reports it. `exit_code` is Slurm's "status:signal" ("0:0", "3:0",
/// "0:9"), empty where the source does not give it (squeue).
struct ElementState {
  int element = -1;
  std::string state;  // COMPLETED, FAILED, PENDING, ... (sacct's "CANCELLED by 0": "CANCELLED")
  std::string exit_code;
};

enum class ElementOutcome { kGoing, kSucceeded, kFailed };
/// kGoing while Slurm may still run the element (PENDING, RUNNING, COMPLETING, REQUEUED, ...),
/// kSucceeded for COMPLETED with exit code 0:0 (or none given), kFailed for any other end.
ElementOutcome element_outcome(const ElementState& e);

/// `squeue -h -r -t all -j JOB -o "%i %T"`: lines "JOB_K STATE"; lines of other jobs, and a
/// pending range that -r did not expand ("JOB_[2-5%2]"), are skipped.
std::vector<ElementState> parse_squeue_elements(const std::string& text, const std::string& job_id);
/// `scontrol show job JOB -o`: one line per element (ArrayJobId=JOB ArrayTaskId=K JobState=...
/// ExitCode=...); an unexpanded pending range ("ArrayTaskId=3-9") is skipped.
std::vector<ElementState> parse_scontrol_elements(const std::string& text,
                                                  const std::string& job_id);
/// `sacct -n -P -X -j JOB -o JobID,State,ExitCode`: lines "JOB_K|STATE|EXIT".
std::vector<ElementState> parse_sacct_elements(const std::string& text, const std::string& job_id);

}  // namespace flexloop::campaign
