// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One shard of a campaign into its JSONL file (`flexloop campaign run plan.json --shard K/M -o
// shard-K.jsonl`, the unit of work every engine calls). Shard K of M holds the evaluation indices
// i with i % M == K, computed in ascending order, one line each, flushed as it is written.
// Idempotent: run again on the same file it reads the lines already there, cuts a damaged tail
// (a torn last line, a zero-filled hole a crash left: a run killed while writing), computes only
// what is missing and never writes an index twice, so a killed shard rerun ends with the same
// bytes as one that was never interrupted. A file of another plan, or with an index of another
// shard, is refused.
//
// One writer per shard file: the writer holds an exclusive flock on it (lock_shard) from before
// it reads the file to its end; a second one (Ctrl-C and resubmit while the first still runs,
// `sbatch --array=K` while K runs, a requeue) is refused naming the holder, instead of two writers
// interleaving lines. A sample whose computation kills its process (a segfault, an OOM kill) is
// written as "error: crashed: ..." instead of killing every rerun at the same index: before each
// sample the writer records it and how many runs started it in FILE.attempt, which a Ctrl-C,
// SIGTERM or SIGHUP removes on the way out and a finished shard deletes. One death in a sample
// may be the machine's (a lost node, a kill -9): it is computed again, and the rerun's bytes are
// those of a run never interrupted. After a second death in the same sample the next run writes
// it as crashed.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/file_lock.hpp"

#include <nlohmann/json.hpp>

namespace flexloop::campaign {

struct Shard {
  long k = 0, m = 1;
};

/// "K/M" with 0 <= K < M. @throws flexloop::InputError naming --shard otherwise.
Shard parse_shard(const std::string& text);

/// The evaluation indices of a shard, ascending.
std::vector<long> shard_indices(const Shard& shard, long evaluations);

/// One line of a shard file, parsed and checked to be of the plan `plan_id`.
/// @throws flexloop::InputError at `place` ("file:line") when it is not a JSON object of it.
nlohmann::json plan_line(const std::string& text, const std::string& place,
                         const std::string& plan_id);

/// The exclusive lock of a shard file (created if missing), held until the pointer is dropped.
/// @throws flexloop::InputError naming the file and the holder's pid when another run holds it.
std::unique_ptr<common::ExclusiveFileLock> lock_shard(const std::string& file);

/// The indices already in a shard file (its complete lines), checked: each line a JSON object
/// of `plan_id`, its index in the shard and not repeated. A damaged tail -- from the first line
/// that is not a JSON object (a torn line, NUL bytes) to the end, with no good line after it --
/// is cut off the file; `repaired` (when given) then says what was cut. The caller holds
/// lock_shard(file). @throws flexloop::InputError "file:line: ..." for a line that breaks these
/// rules before the tail.
std::vector<long> completed_indices(const std::string& file, const std::string& plan_id,
                                    const Shard& shard, long evaluations,
                                    std::string* repaired = nullptr);

struct ShardRunResult {
  long already = 0, computed = 0;
  long crashed = 0;  ///< samples written as "error: crashed" (two runs died computing them)
};

/// The line of a sample that was not computed: `status` ("error: crashed: ...") and null figures.
using FailedLine = std::function<nlohmann::json(long index, const std::string& status)>;

/// Computes the shard's missing lines with `line_of(index)` (the JSONL object) and appends each,
/// one per line; `progress(done, total)` after each (done counts the lines already there). A
/// sample that killed the last two runs (FILE.attempt names it) is written as
/// `failed_line(index, "error: crashed: ...")` (without one: plan_id, index and status only).
/// The caller holds lock_shard(file).
ShardRunResult run_shard(const std::string& file, const std::string& plan_id, const Shard& shard,
                         long evaluations, const std::function<nlohmann::json(long)>& line_of,
                         const FailedLine& failed_line = {},
                         const std::function<void(long, long)>& progress = {});

/// The number of complete lines ('\n'-terminated) of a file; 0 when it does not exist.
long complete_lines(const std::string& file);

/// complete_lines for files that grow while they are watched (an engine's progress, every 250
/// ms): each call reads only the bytes appended since the last one, so that watching a shard to
/// its end costs one pass over it, not one per tick. A file that shrank (a damaged tail cut) is
/// counted again from its start.
class GrowingLineCount {
 public:
  long lines(const std::string& file);

 private:
  struct Seen {
    std::uintmax_t bytes = 0;
    long lines = 0;
  };
  std::map<std::string, Seen> seen_;
};

}  // namespace flexloop::campaign
