// SPDX-License-Identifier: BSD-3-Clause
// `flexloop roudi [--duration S]`: iceoryx's RouDi for loops run by hand over shared memory
// (`flexloop plant|controller --transport iceoryx`, an external controller on iceoryx's C
// binding). It starts iox-roudi with a config sized for flexloop's messages, says when it is
// ready, and stops it by its pid on SIGINT / SIGTERM or after --duration, leaving no segment,
// socket or lock file behind (rt/roudi_process.hpp). `flexloop hil --transport iceoryx` and
// `flexloop baseline pingpong --transport iceoryx` start their own.
#include <unistd.h>

#include <cstdio>
#include <memory>

#include "online/loop/stop_signal.hpp"
#include "rt/loop_transport.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/roudi_process.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

void run_roudi(double duration_s) {
  loop::install_stop_handlers();
  const rt::RoudiOptions options = rt::loop_roudi_options();
  rt::RoudiProcess roudi(options);
  std::printf(
      "roudi: iox-roudi (pid %d) ready: %u chunks of %u bytes for flexloop's messages; stop "
      "with Ctrl-C or SIGTERM\n",
      static_cast<int>(roudi.pid()), options.mempools.front().count,
      options.mempools.front().chunk_bytes);
  std::fflush(stdout);
  const std::int64_t end =
      duration_s > 0 ? rt::monotonic_now_ns() + static_cast<std::int64_t>(duration_s * 1e9)
                     : INT64_MAX;
  while (!loop::stop_requested() && rt::monotonic_now_ns() < end) {
    if (!roudi.alive()) throw rt::RoudiError(roudi.describe() + ": RouDi ended by itself");
    usleep(20'000);
  }
  roudi.stop();
  std::printf("roudi: stopped\n");
}

}  // namespace

void register_roudi(CLI::App& app) {
  auto duration_s = std::make_shared<double>(0);
  auto* cmd = app.add_subcommand(
      "roudi", "iceoryx's RouDi for plant and controller processes run with --transport iceoryx");
  cmd->add_option("--duration", *duration_s, "Stop after this long [s] (default: until stopped)")
      ->check(finite_range(0.0, 1e9));
  cmd->footer(
      "One RouDi per host (iceoryx 2.0): refused when one already runs. It ends with this\n"
      "process (also when it is killed); the processes still registered are told to end.\n"
      "Example:\n"
      "  flexloop roudi &\n"
      "  flexloop controller loop.json --transport iceoryx --rate 20000 &\n"
      "  flexloop plant loop.json --transport iceoryx --rate 20000 --duration 5\n"
      "  kill %2 %1");
  cmd->callback([duration_s] { run_roudi(*duration_s); });
}

}  // namespace flexloop::cli
