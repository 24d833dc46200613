// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A recorded run (`flexloop hil --lcm-log FILE`, an LCM log) as a table for MATLAB, Octave and
// Python users: one row per sensor sample, columns named from the channel map the log carries
// (FLEXLOOP_CHANNEL_MAP, online/loop/channel_map.hpp):
//   t_s                  the sample's plant time from the first sample [s]
//   seq                  the sample number
//   sensor <name> [unit], performance <name> [unit]   the sample's readings
//   command <name> [unit]                             the answer to that sample; NaN when no
//                                                     answer to it is in the log
// Written as CSV or as a MATLAB .mat file (offline/report/table_file.hpp).
// Bad input: flexloop::InputError naming the log file.
#include <string>
#include <vector>

namespace flexloop::report {

struct RunTable {
  std::string loop;                          ///< the loop's name in the channel map
  std::vector<std::string> names;            ///< one per column
  std::vector<std::vector<double>> columns;  ///< equally long
  long answered = 0;                         ///< samples with their answer in the log
};

/// @throws flexloop::InputError naming `path` when it cannot be read as an LCM log, has no channel
/// map, or holds messages whose channel counts differ from the map's.
RunTable read_run_log(const std::string& path);

/// CSV or .mat by the extension of `path` (".csv", ".mat"); written atomically.
/// @throws flexloop::InputError for another extension; std::runtime_error when it cannot be
/// written.
void write_run_table(const RunTable& table, const std::string& path);

}  // namespace flexloop::report
