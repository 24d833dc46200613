#pragma once
// One shard of a campaign into its JSONL file (`flexloop campaign run plan.json --shard K/M -o
// shard-K.jsonl`, the unit of work every engine calls). Shard K of M holds the evaluation indices
// i with i % M == K, computed in ascending order, one line each, flushed as it is written.
// Idempotent: run again on the same file it reads the lines already there, drops a torn last
// line (a run killed while writing it), computes only what is missing and never writes an index
// twice, so a killed shard rerun ends with the same bytes as one that was never interrupted.
// A file of another plan, or with an index of another shard, is refused.
#include <functional>
#include <string>
#include <vector>

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

/// The indices already in a shard file (its complete lines), checked: each line a JSON object
/// of `plan_id`, its index in the shard and not repeated. A torn last line is cut off the file.
/// @throws flexloop::InputError "file:line: ..." for a line that breaks these rules.
std::vector<long> completed_indices(const std::string& file, const std::string& plan_id,
                                    const Shard& shard, long evaluations);

struct ShardRunResult {
  long already = 0, computed = 0;
};

/// Computes the shard's missing lines with `line_of(index)` (the JSONL object) and appends each,
/// one per line; `progress(done, total)` after each (done counts the lines already there).
ShardRunResult run_shard(const std::string& file, const std::string& plan_id, const Shard& shard,
                         long evaluations, const std::function<nlohmann::json(long)>& line_of,
                         const std::function<void(long, long)>& progress = {});

/// The number of complete lines ('\n'-terminated) of a file; 0 when it does not exist.
long complete_lines(const std::string& file);

}  // namespace flexloop::campaign
