// SPDX-License-Identifier: BSD-3-Clause
// The Slurm engine against a running Slurm (hidden: tests/campaign/slurm_engine.sh starts a
// single-node cluster with tools/slurm/start-local-cluster and runs this with SLURM_CONF set).
//
// This is a test of the ENGINE, not of the campaign: the program the array elements run is a
// stand-in for flexloop (a shell script written here) that keeps the contract of
// `flexloop campaign run PLAN --shard K/M -o FILE` (doc/campaign_slurm.md): it appends one line per
// index i < N with i % M == K, skips the lines already there (idempotent), and fails with exit 3
// after its first new line while a file fail-K lies beside the shard files; while a file
// requeue-K lies there, its first attempt requeues its own element (scontrol requeue) after its
// first new line. The campaign itself through Slurm is tests/campaign/slurm_campaign.sh.
//
// Asserted: a submission with one failing element is an error naming that element (job_K), its
// state FAILED, its exit code 3:0 and the stand-in's last words from its log, while the other
// shard files are complete; submitting again (the fault gone) completes the failed shard, so
// that every index 0..N-1 is in exactly one shard file, in its shard, once. An element requeued
// mid-way completes its shard without a duplicate, and its log holds both attempts
// (--open-mode=append: without it Slurm truncates the log when the element starts again); the
// --sbatch-arg lines reach the job as sbatch reads them (a quoted comment with a blank).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "offline/campaign/slurm_engine.hpp"
#include "tests/campaign/slurm_test_support.hpp"

using namespace flexloop::campaign;
using flexloop::campaign::test::read_file;
using flexloop::campaign::test::ScratchDir;
using flexloop::campaign::test::write_file;

namespace {

// `campaign run` as the contract has it, for plans that are just a number of indices.
const char* const kStandIn = R"(#!/bin/bash
set -eu
[ "$1 $2 $4 $6" = "campaign run --shard -o" ] || { echo "stand-in: bad arguments: $*" >&2; exit 64; }
plan=$3 k=${5%/*} m=${5#*/} out=$7
n=$(cat "$plan")
attempt=${SLURM_RESTART_COUNT:-0}
echo "stand-in: shard $k attempt $attempt" >&2
touch "$out"
for ((i = k; i < n; i += m)); do
  grep -qx "{\"index\":$i}" "$out" && continue
  echo "{\"index\":$i}" >> "$out"
  if [ -e "$(dirname "$out")/fail-$k" ]; then
    echo "stand-in: shard $k told to fail after index $i" >&2
    exit 3
  fi
  if [ -e "$(dirname "$out")/requeue-$k" ] && [ "$attempt" = 0 ]; then
    echo "stand-in: shard $k requeues itself after index $i" >&2
    # The element, not the array (the last element's own job id is the array's too); then wait
    # to be killed as the element's process itself (exec): with a `sleep` child instead, Slurm's
    # signals once left it running here and drained the node ("Kill task failed").
    scontrol requeue "${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}"
    exec sleep 600
  fi
done
)";

// The indices in one shard file, each line checked to be one index once.
std::multiset<int> indices_in(const std::string& path) {
  std::multiset<int> indices;
  std::istringstream in(read_file(path));
  for (std::string line; std::getline(in, line);) {
    REQUIRE(line.rfind("{\"index\":", 0) == 0);
    indices.insert(std::stoi(line.substr(9)));
  }
  return indices;
}

// Options for `shards` elements of the stand-in (written into the scratch directory), its shard
// files and logs in scratch/work_dir.
SlurmOptions stand_in_options(const ScratchDir& scratch, int shards, const std::string& work_dir) {
  SlurmOptions o;
  o.shards = shards;
  o.time_limit_min = 5;
  o.work_dir = scratch / work_dir;
  o.flexloop_program = scratch / "stand-in flexloop";
  write_file(o.flexloop_program, kStandIn, true);
  return o;
}

// A plan of the stand-in's: its number of indices.
std::string plan_of(const ScratchDir& scratch, int n) {
  const std::string plan = scratch / "plan.json";
  write_file(plan, std::to_string(n) + "\n");
  return plan;
}

// Every index 0..n-1 once, each in the shard file of its shard.
void check_complete(const std::vector<std::string>& files, int n) {
  const int shards = static_cast<int>(files.size());
  std::multiset<int> all;
  for (int k = 0; k < shards; ++k)
    for (const int i : indices_in(files[k])) {
      CHECK(i % shards == k);
      all.insert(i);
    }
  std::multiset<int> every;
  for (int i = 0; i < n; ++i) every.insert(i);
  CHECK(all == every);
}

// The job of the logs in a work directory ("campaign-<job>_<K>.err"); empty when there are none.
std::string job_of_logs(const std::string& work_dir) {
  const std::regex log_name(R"(campaign-(\d+)_\d+\.err)");
  std::smatch m;
  for (const auto& entry : std::filesystem::directory_iterator(work_dir)) {
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, m, log_name)) return m[1].str();
  }
  return "";
}

}  // namespace

TEST_CASE("slurm engine: a failed element is named with its log, a resubmission completes it",
          "[.][slurm_cluster]") {
  REQUIRE(std::getenv("SLURM_CONF") != nullptr);
  ScratchDir scratch("slurm engine");
  SlurmOptions o = stand_in_options(scratch, 3, "work dir");  // a blank, as users' directories have
  o.array_throttle = 2;
  const int n = 11;
  const std::string plan = plan_of(scratch, n);
  write_file(o.work_dir + "/fail-1", "");

  std::string error;
  try {
    submit_slurm(plan, o);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  INFO(error);
  CHECK(error.find("1 of 3 elements failed") != std::string::npos);
  CHECK(error.find("_1 (shard 1/3): FAILED, exit code 3:0") != std::string::npos);
  CHECK(error.find("stand-in: shard 1 told to fail after index 1") != std::string::npos);
  CHECK(indices_in(slurm_shard_file(o, 0)) == std::multiset<int>{0, 3, 6, 9});
  CHECK(indices_in(slurm_shard_file(o, 1)) == std::multiset<int>{1});
  CHECK(indices_in(slurm_shard_file(o, 2)) == std::multiset<int>{2, 5, 8});

  std::filesystem::remove(o.work_dir + "/fail-1");
  const std::vector<std::string> files = submit_slurm(plan, o);
  REQUIRE(files.size() == 3);
  for (int k = 0; k < 3; ++k) CHECK(files[k] == slurm_shard_file(o, k));
  check_complete(files, n);
  CHECK(std::filesystem::exists(o.work_dir + "/campaign.sbatch"));
}

TEST_CASE("slurm engine: a requeued element completes its shard and its log keeps both attempts",
          "[.][slurm_cluster]") {
  REQUIRE(std::getenv("SLURM_CONF") != nullptr);
  ScratchDir scratch("slurm requeue");
  SlurmOptions o = stand_in_options(scratch, 2, "work");
  o.sbatch_args = {"--comment=\"flexloop requeue test\"", "--mem=64M"};
  const int n = 9;
  const std::string plan = plan_of(scratch, n);
  write_file(o.work_dir + "/requeue-1", "");

  const std::vector<std::string> files = submit_slurm(plan, o);
  REQUIRE(files.size() == 2);
  check_complete(files, n);
  const std::string job = job_of_logs(o.work_dir);
  REQUIRE(!job.empty());
  const std::string log = read_file(slurm_log_file(o, job, 1, "err"));
  INFO(log);
  const std::size_t first = log.find("stand-in: shard 1 attempt 0");
  const std::size_t requeued = log.find("stand-in: shard 1 requeues itself after index 1");
  const std::size_t second = log.find("stand-in: shard 1 attempt 1");
  CHECK(first != std::string::npos);
  CHECK(requeued != std::string::npos);
  CHECK(second != std::string::npos);
  CHECK((first < requeued && requeued < second));
  // The element knew it was requeued; the --sbatch-arg lines reached the job.
  const std::string scontrol_out = scratch / "scontrol.txt";
  REQUIRE(std::system(("scontrol show job " + job + "_1 -o > '" + scontrol_out + "'").c_str()) ==
          0);
  const std::string record = read_file(scontrol_out);
  INFO(record);
  CHECK(record.find("Restarts=1") != std::string::npos);
  CHECK(record.find("Comment=flexloop requeue test ") != std::string::npos);
  CHECK(record.find("MinMemoryNode=64M") != std::string::npos);
}
