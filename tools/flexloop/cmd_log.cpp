// SPDX-License-Identifier: BSD-3-Clause
// `flexloop log LOG -o OUT.csv|OUT.mat`: a recorded run (`flexloop hil --lcm-log LOG`) as a table
// for MATLAB, Octave and Python (offline/report/run_log.hpp has the columns); a table (`flexloop
// sim --log`, or this command's own) LOG.csv or LOG.mat into the other format, value for value.
#include <cstdio>
#include <memory>
#include <string>

#include "common/atomic_file.hpp"
#include "offline/report/run_log.hpp"
#include "offline/report/table_file.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

void register_log(CLI::App& app) {
  struct Args {
    std::string log, out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "log",
      "Export a recorded run (an LCM log of flexloop hil --lcm-log) to CSV or .mat, or convert a "
      "table (.csv, .mat of flexloop sim --log) into the other format");
  cmd->add_option("log", args->log,
                  "LCM log written by flexloop hil --lcm-log, or a table LOG.csv / LOG.mat")
      ->required();
  cmd->add_option("-o,--output", args->out,
                  "Table to write: OUT.csv (one row per sample) or OUT.mat (data, columns)")
      ->required();
  cmd->footer(
      "Columns: t_s, seq, sensor <name> [unit]..., performance <name> [unit]..., command <name> "
      "[unit]... (NaN where a sample's answer is not in the log).\n"
      "Example:\n"
      "  flexloop hil tools/scenes/metrology_frame.toml --netns --duration 2 --report out/hil.json "
      "--lcm-log out/run.lcmlog\n"
      "  flexloop log out/run.lcmlog -o out/run.mat\n"
      "  flexloop log out/sim.mat -o out/sim.csv");
  cmd->callback([args] {
    common::require_writable(args->out);     // before the work, not after it
    if (report::is_table_file(args->log)) {  // a table: into the other format
      const report::Table t = report::read_table(args->log);
      report::write_table(args->out, t.names, t.data);
      std::printf("%s: %ld rows, %ld columns\nwrote %s\n", args->log.c_str(),
                  static_cast<long>(t.data.rows()), static_cast<long>(t.data.cols()),
                  args->out.c_str());
      return;
    }
    const report::RunTable t = report::read_run_log(args->log);
    report::write_run_table(t, args->out);
    const std::size_t rows = t.columns.empty() ? 0 : t.columns[0].size();
    std::printf("%s: loop %s, %zu samples (%ld with their answer), %zu columns\nwrote %s\n",
                args->log.c_str(), t.loop.c_str(), rows, t.answered, t.names.size(),
                args->out.c_str());
  });
}

}  // namespace flexloop::cli
