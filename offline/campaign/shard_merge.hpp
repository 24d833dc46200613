#pragma once
// The shard files of a campaign merged into its samples (`flexloop campaign report`): every line
// checked to be the plan's, every evaluation index present once; sorted by index. The merged
// samples.jsonl is the lines as the shards wrote them, so it is byte-identical whatever the
// sharding and the engine.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace flexloop::campaign {

struct MergedSamples {
  std::vector<nlohmann::json> samples;  ///< sorted by index, one per evaluation
  std::string jsonl;                    ///< their lines as written, in index order
};

/// @throws flexloop::InputError "file:line: ..." for a line of another plan (or not JSON, or an
/// index outside the plan, or an index two shards give differently); and naming the plan when
/// samples are missing, with their indices (as ranges) and how to complete them.
MergedSamples merge_shards(const nlohmann::json& plan, const std::vector<std::string>& files);

/// "0-4, 9, 12-13": sorted indices as ranges.
std::string index_ranges(const std::vector<long>& sorted_indices, std::size_t at_most = 20);

}  // namespace flexloop::campaign
