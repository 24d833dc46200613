// SPDX-License-Identifier: BSD-3-Clause
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
  int shards = 0;                  // 0: the default, slurm_shard_count's
  long evaluations = 0;            // the plan's, for the default shard count
  int array_throttle = 0;          // %N on --array; 0: none
  std::string flexloop_program;    // absolute path of the flexloop executable to run
  std::string work_dir;            // where the script, the shard files and Slurm's logs go
  double time_limit_min = 60;
  // More sbatch options (--mem=4G, --qos=long, -M other, ...): each written verbatim as its own
  // `#SBATCH` line, read by sbatch as it reads any such line.
  std::vector<std::string> sbatch_args;
};

/// The default shard count: one shard per this many of the plan's evaluations. At the metrology
/// frame's 20 to 40 ms a sample a shard runs about a minute, against the second or two of an
/// array element's scheduling (doc/campaign_slurm.md, "Why a shard holds many samples").
constexpr long kEvaluationsPerShard = 2000;
/// Slurm's MaxArraySize when `scontrol show config` does not say.
constexpr int kSlurmDefaultMaxArraySize = 1001;

struct ShardCount {
  int shards = 0;
  std::string note;  // how a default was chosen (empty for a count the user gave)
};
/// The array's shard count under the cluster's MaxArraySize (indices 0 to MaxArraySize - 1, so
/// at most MaxArraySize elements). `requested` > 0: that count, an InputError naming --shards
/// when above MaxArraySize (capping it would lengthen every element past the --time-limit chosen
/// for it). 0: ceil(evaluations / kEvaluationsPerShard), at least 1, capped at MaxArraySize.
/// MaxArraySize 0 (arrays disabled on the cluster) is a std::runtime_error.
ShardCount slurm_shard_count(int requested, long evaluations, int max_array_size);

/// MaxArraySize in `scontrol show config` ("MaxArraySize            = 1001"); the smallest when
/// several clusters' configurations are listed; -1 when none is.
int parse_max_array_size(const std::string& scontrol_config);

/// The cluster a list of sbatch options names with -M NAME, -MNAME, --clusters=NAME or
/// --cluster=NAME (the last one given); empty when none does.
std::string cluster_of_sbatch_args(const std::vector<std::string>& sbatch_args);

/// A submitted job: `sbatch --parsable` prints "JOBID" or, for a job on another cluster (-M),
/// "JOBID;CLUSTER". squeue, scontrol, sacct and scancel reach that job only with -M CLUSTER.
struct SubmittedJob {
  std::string id, cluster;  // cluster empty: the local one
};
/// The job of sbatch --parsable's output; id empty when the output is neither form.
SubmittedJob parse_sbatch_parsable(const std::string& out);

/// Reads MaxArraySize (scontrol show config, of the cluster the sbatch options name) and chooses
/// the shard count (slurm_shard_count); writes work_dir/campaign.sbatch: an array 0..shards-1
/// whose element K runs `<flexloop> campaign run <plan> --shard K/<shards> -o
/// <work_dir>/shard-K.jsonl`; submits it (sbatch --parsable), waits (squeue, then scontrol or
/// sacct, with -M CLUSTER when sbatch named one) with progress on stderr, and returns the shard
/// files in shard order. Options that Slurm could not take (a partition name with a blank, a
/// work_dir with '%' or '"', shards above MaxArraySize, a relative program path, an sbatch option
/// with a newline or one the engine writes itself) are common::InputError; a failed element
/// (FAILED, TIMEOUT, CANCELLED, NODE_FAIL, OUT_OF_MEMORY, ... or a non-zero exit code) is a
/// std::runtime_error naming every failed element, its state and exit code, and the last lines of
/// its log. `campaign run` is idempotent: calling this again after a failure completes the shards
/// that are missing samples.
std::vector<std::string> submit_slurm(const std::string& plan_path, const SlurmOptions& o);

// The parts of submit_slurm, for the tests and for a user who submits the script by hand.

/// work_dir/shard-K.jsonl
std::string slurm_shard_file(const SlurmOptions& o, int shard);
/// Slurm's logs of element `shard` of job `job_id`: work_dir/campaign-<job>_<K>.out and .err.
std::string slurm_log_file(const SlurmOptions& o, const std::string& job_id, int shard,
                           const std::string& extension);

/// The text of campaign.sbatch for an absolute plan path (options checked as submit_slurm does,
/// o.shards >= 1). Elements are requeueable (--requeue: a node that fails requeues its elements)
/// and their logs are opened with --open-mode=append, so a requeued element's log keeps the
/// attempt before; the shard it reruns is completed, not duplicated (`campaign run` resumes).
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
