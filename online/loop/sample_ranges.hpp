// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The samples (by seq) where a run departed from the ideal loop, kept as ranges: the answers
// the plant did not apply (a deadline miss: it held or went safe) and the samples the controller
// did not answer. Together with the artefact they determine the run sample for sample, which is
// what online/hil/run_replay.hpp replays. Recording allocates nothing (the capacity is reserved
// at set-up); a run with more ranges than that says so (complete() false) and cannot be replayed.
#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

namespace flexloop::loop {

class SampleRanges {
 public:
  /// Ranges kept at most (each one seq or a run of consecutive ones).
  static constexpr std::size_t kCapacity = 1 << 16;

  SampleRanges() { ranges_.reserve(kCapacity); }

  /// Adds seqs first..last (ascending calls; consecutive ones merge).
  void add(std::int64_t first, std::int64_t last) noexcept {
    if (last < first) return;
    if (!ranges_.empty() && ranges_.back().second + 1 >= first) {
      ranges_.back().second = std::max(ranges_.back().second, last);
      return;
    }
    if (ranges_.size() == kCapacity) {
      complete_ = false;
      return;
    }
    ranges_.emplace_back(first, last);
  }
  void add(std::int64_t seq) noexcept { add(seq, seq); }
  /// Something the ranges cannot say happened (a second plant run answered, too many ranges).
  void mark_incomplete() noexcept { complete_ = false; }

  bool complete() const noexcept { return complete_; }
  const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges() const noexcept {
    return ranges_;
  }
  /// The seqs in all ranges.
  std::int64_t count() const noexcept {
    std::int64_t n = 0;
    for (const auto& [first, last] : ranges_) n += last - first + 1;
    return n;
  }

  /// {"ranges": [[first, last], ...], "complete": bool}
  nlohmann::json to_json() const {
    nlohmann::json ranges = nlohmann::json::array();
    for (const auto& [first, last] : ranges_) ranges.push_back({first, last});
    return {{"ranges", std::move(ranges)}, {"complete", complete_}};
  }
  /// The inverse of to_json. @throws nlohmann::json::exception on another shape.
  static SampleRanges from_json(const nlohmann::json& j) {
    SampleRanges r;
    for (const auto& range : j.at("ranges"))
      r.add(range.at(0).get<std::int64_t>(), range.at(1).get<std::int64_t>());
    if (!j.at("complete").get<bool>()) r.mark_incomplete();
    return r;
  }

 private:
  std::vector<std::pair<std::int64_t, std::int64_t>> ranges_;
  bool complete_ = true;
};

}  // namespace flexloop::loop
