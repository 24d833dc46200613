// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// CSV tables for reports: one header row of column names, then numeric rows (RFC 4180 quoting
// for names that need it). Numbers are written in the shortest form that reads back to the same
// double (std::to_chars), non-finite values as nan / inf / -inf.
//
// Files are written atomically: the text goes to a temporary file in the target directory,
// which is flushed to disk and renamed over the target, so a reader never sees half a table and
// a failed write leaves no file behind (plant/lti/atomic_file.hpp, shared by every artefact).
#include <Eigen/Dense>
#include <string>
#include <vector>

namespace flexloop::report {

/// Write `data` (one row per record, one column per header entry) to `path`.
/// @throws std::invalid_argument when header.size() != data.cols();
/// @throws std::runtime_error naming the file when it cannot be written.
void write_csv(const std::string& path, const std::vector<std::string>& header,
               Eigen::Ref<const Eigen::MatrixXd> data);

/// Same, from equally long columns (columns[j] is the column named header[j]).
void write_csv_columns(const std::string& path, const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& columns);

/// Shortest decimal text that reads back to exactly `v`; "nan", "inf", "-inf" otherwise.
std::string format_number(double v);

}  // namespace flexloop::report
