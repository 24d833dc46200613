// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The shard files of a campaign merged into its samples (`flexloop campaign report`): every line
// checked to be the plan's, every evaluation index present once; sorted by index. The merged
// samples.jsonl is the lines as the shards wrote them, so it is byte-identical whatever the
// sharding and the engine.
//
// The merge streams: each line is read and parsed once, handed to the caller and dropped. What it
// keeps per evaluation is where its line is (file, offset, length: 16 bytes), from which
// samples.jsonl is copied in index order and a few lines (the worst samples) read again: a
// 10^6-sample campaign's 5 GB of lines are never held (issue 54).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace flexloop::campaign {

/// Where each evaluation's line is in the shard files (the first file and line that gave it).
class ShardLines {
 public:
  ShardLines(std::vector<std::string> files, long evaluations);

  /// The line of an evaluation as written, its '\n' included; "" when no file gave it.
  std::string line(long index) const;
  /// "file:line" of an evaluation's line.
  std::string place(long index) const;
  bool has(long index) const { return places_[static_cast<std::size_t>(index)].length > 0; }
  /// Every line in index order (those given), written atomically to `file` in pieces.
  void write_in_index_order(const std::filesystem::path& file) const;

  /// Records an evaluation's line (the merge, once per index).
  void record(long index, std::uint32_t file, std::uint64_t offset, std::uint32_t length);

 private:
  struct Place {
    std::uint64_t offset = 0;
    std::uint32_t length = 0, file = 0;  ///< length 0: no line yet
  };
  std::vector<std::string> files_;
  std::vector<Place> places_;
};

/// A line, parsed, of the given evaluation index: the first of that index among the files.
using TakeSample = std::function<void(long index, const nlohmann::json& sample)>;

/// Reads every shard file line by line, checks each line, hands each index's first line to
/// `take` (in the order of the files) and returns where the lines are.
/// @throws flexloop::InputError "file:line: ..." for a line of another plan (or not JSON, or an
/// index outside the plan, or an index two shards give differently, or a torn last line), for
/// lines of two builds; and naming the plan when samples are missing, with their indices (as
/// ranges) and how to complete them. Every line is checked before any of these but the
/// first-line errors is thrown: the errors are those of a merge that read every file first.
ShardLines merge_shards(const nlohmann::json& plan, const std::vector<std::string>& files,
                        const TakeSample& take);

struct MergedSamples {
  std::vector<nlohmann::json> samples;  ///< sorted by index, one per evaluation
  std::string jsonl;                    ///< their lines as written, in index order
};

/// The merge held in memory (a small campaign, tests): the samples and their lines.
MergedSamples merge_shards(const nlohmann::json& plan, const std::vector<std::string>& files);

/// "0-4, 9, 12-13": sorted indices as ranges.
std::string index_ranges(const std::vector<long>& sorted_indices, std::size_t at_most = 20);

}  // namespace flexloop::campaign
