// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Columns of numbers too large to hold in memory, filled a row at a time: a campaign's sigma
// curves (one value per grid frequency per stable machine: 206 x 8 bytes a sample, 1.6 GB at
// 10^6 samples), read back one column at a time (the envelope's quantiles at one frequency).
// Each column gathers its values in a chunk of 64 KiB; a full chunk goes to an unlinked
// temporary file (TMPDIR), so the memory held is one chunk per column, whatever the rows.
#include <cstdint>
#include <string>
#include <vector>

namespace flexloop::campaign {

class ColumnSpill {
 public:
  explicit ColumnSpill(std::size_t columns = 0);
  ~ColumnSpill();
  ColumnSpill(ColumnSpill&& other) noexcept;
  ColumnSpill& operator=(ColumnSpill&& other) noexcept;
  ColumnSpill(const ColumnSpill&) = delete;
  ColumnSpill& operator=(const ColumnSpill&) = delete;

  std::size_t columns() const { return pending_.size(); }
  /// Appends a value to a column. @throws std::runtime_error when the file cannot be written.
  void push(std::size_t column, double value);
  /// A column's values in the order they were pushed.
  std::vector<double> column(std::size_t column) const;

 private:
  static constexpr std::size_t kChunk = 8192;  // values (64 KiB) per write
  void spill(std::size_t column);

  std::vector<std::vector<double>> pending_;        // per column: the values not yet written
  std::vector<std::vector<std::uint64_t>> chunks_;  // per column: its full chunks' file offsets
  int fd_ = -1;
  std::uint64_t end_ = 0;
};

}  // namespace flexloop::campaign
