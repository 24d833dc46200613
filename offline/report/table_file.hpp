// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A numeric table with named columns written for MATLAB, Octave and Python users, the format
// chosen by the file's extension:
//   .csv  text (offline/report/csv_writer.hpp)
//   .mat  MATLAB MAT 5 (libmatio): `data` (rows x columns, double, as stored) and `columns` (a
//         cell array of the column names); binary, no formatting: what long runs should use.
// Written atomically: a failed write leaves no file behind.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace flexloop::report {

/// True for the extensions write_table() takes (".csv", ".mat").
bool is_table_file(const std::string& path);

/// @throws flexloop::InputError naming `path` for another extension; std::invalid_argument when
/// names.size() != data.cols(); std::runtime_error when it cannot be written.
void write_table(const std::string& path, const std::vector<std::string>& names,
                 Eigen::Ref<const Eigen::MatrixXd> data);

/// write_table() in two steps, so that the slow one can run beside other work: stage_table()
/// writes the whole file under PATH.tmp, where nobody reading `path` sees it (same
/// errors as write_table(); a failed write leaves nothing); commit_table() puts it in place with
/// one rename; discard_table() removes it.
void stage_table(const std::string& path, const std::vector<std::string>& names,
                 Eigen::Ref<const Eigen::MatrixXd> data);
void commit_table(const std::string& path);
void discard_table(const std::string& path) noexcept;

/// A table as write_table() wrote it (`flexloop log` converts one format into the other).
struct Table {
  std::vector<std::string> names;
  Eigen::MatrixXd data;
};

/// Reads a .csv (a header row, then equally long rows of numbers; nan / inf as written) or a
/// .mat (`data`, a real double matrix, and `columns`, a cell array of its column names).
/// @throws flexloop::InputError naming the file, and the line (CSV) or variable (.mat) at fault.
Table read_table(const std::string& path);

}  // namespace flexloop::report
