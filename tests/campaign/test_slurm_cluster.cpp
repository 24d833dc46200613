// The Slurm engine against a running Slurm (hidden: tests/campaign/slurm_engine.sh starts a
// single-node cluster with tools/slurm/start-local-cluster and runs this with SLURM_CONF set).
//
// This is a test of the ENGINE, not of the campaign: the program the array elements run is a
// stand-in for flexloop (a shell script written here) that keeps the contract of
// `flexloop campaign run PLAN --shard K/M -o FILE` (doc/campaign_slurm.md): it appends one line per
// index i < N with i % M == K, skips the lines already there (idempotent), and fails with exit 3
// after its first new line while a file fail-K lies beside the shard files. The campaign itself
// through Slurm is tests/campaign/slurm_campaign.sh.
//
// Asserted: a submission with one failing element is an error naming that element (job_K), its
// state FAILED, its exit code 3:0 and the stand-in's last words from its log, while the other
// shard files are complete; submitting again (the fault gone) completes the failed shard, so
// that every index 0..N-1 is in exactly one shard file, in its shard, once.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
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
touch "$out"
for ((i = k; i < n; i += m)); do
  grep -qx "{\"index\":$i}" "$out" && continue
  echo "{\"index\":$i}" >> "$out"
  if [ -e "$(dirname "$out")/fail-$k" ]; then
    echo "stand-in: shard $k told to fail after index $i" >&2
    exit 3
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

}  // namespace

TEST_CASE("slurm engine: a failed element is named with its log, a resubmission completes it",
          "[.][slurm_cluster]") {
  REQUIRE(std::getenv("SLURM_CONF") != nullptr);
  ScratchDir scratch("slurm engine");
  SlurmOptions o;
  o.shards = 3;
  o.array_throttle = 2;
  o.time_limit_min = 5;
  o.work_dir = scratch / "work dir";  // a blank, as users' directories have
  o.flexloop_program = scratch / "stand-in flexloop";
  write_file(o.flexloop_program, kStandIn, true);
  const int n = 11;
  const std::string plan = scratch / "plan.json";
  write_file(plan, std::to_string(n) + "\n");
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
  std::multiset<int> all;
  for (int k = 0; k < 3; ++k) {
    CHECK(files[k] == slurm_shard_file(o, k));
    for (const int i : indices_in(files[k])) {
      CHECK(i % 3 == k);
      all.insert(i);
    }
  }
  std::multiset<int> every;
  for (int i = 0; i < n; ++i) every.insert(i);
  CHECK(all == every);
  CHECK(std::filesystem::exists(o.work_dir + "/campaign.sbatch"));
}
