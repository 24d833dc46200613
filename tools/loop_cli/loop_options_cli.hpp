// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Command-line options shared by `flexloop plant`, `controller` and `hil` and the online programs
// flexloop-plant and flexloop-controller (online/loop/loop_options.hpp): --rate, --wait,
// --spin-margin-us, --receive-path, --transport, --cpu, --priority, --no-mlock,
// --safe-after, --start, --url, --link. apply_loop_options() turns the parsed text into
// LoopOptions.
#include <CLI/CLI.hpp>
#include <string>

#include "online/loop/loop_options.hpp"

namespace flexloop::cli {

/// What --transport iceoryx needs of the plant and controller processes.
inline const std::string kRoudiNeeded =
    "a RouDi must run on this host: flexloop roudi, or iox-roudi";

struct LoopArgs {
  loop::LoopOptions options;
  std::string wait = rt::to_string(loop::LoopOptions{}.wait);
  std::string receive_path = rt::to_string(loop::LoopOptions{}.receive_path);
  std::string transport = rt::to_string(loop::LoopOptions{}.transport);
  double spin_margin_us = rt::kDefaultSpinMarginNs / 1e3;
  bool no_mlock = false;
  std::string start = "stationary";
  double max_miss_percent = 100 * loop::RunLimits{}.max_miss_share;
};

/// --wait sleep|hybrid|spin and --spin-margin-us (also used by `flexloop baseline`).
void add_wait_options(CLI::App* cmd, std::string& wait, double& spin_margin_us);
/// --receive-path lcm-thread|direct (also used by `flexloop baseline pingpong`).
void add_receive_path_option(CLI::App* cmd, std::string& path);
/// --transport lcm|iceoryx (also used by `flexloop baseline pingpong`); `iceoryx` says what
/// starts RouDi for this command.
void add_transport_option(CLI::App* cmd, std::string& transport, const std::string& iceoryx);
/// --cpu, --priority, --no-mlock (also used by `flexloop baseline`).
void add_realtime_options(CLI::App* cmd, int& cpu, int& priority, bool& no_mlock);

/// Adds the shared options; default_cpu is the process's usual core (plant 0, controller 1);
/// loop_help says what the positional `loop` file may be; roudi_help who starts RouDi for
/// --transport iceoryx.
void add_loop_options(CLI::App* cmd, LoopArgs& a, int default_cpu, const std::string& loop_help,
                      const std::string& roudi_help);
/// --safe-ramp (the plant's, and hil's, which hands it to the plant).
void add_safe_ramp_option(CLI::App* cmd, LoopArgs& a);
/// --max-miss-share and --stop-after-misses: the verdict of a real-time run (plant, hil).
void add_verdict_options(CLI::App* cmd, LoopArgs& a);
/// The options as parsed (wait mode, margin, memory locking applied).
loop::LoopOptions apply_loop_options(const LoopArgs& a);

}  // namespace flexloop::cli
