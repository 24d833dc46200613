// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Each subcommand lives in its own cmd_<name>.cpp and registers itself on the main app.
// A subcommand's callback throws flexloop::InputError for bad input (exit 2) and
// std::exception for other failures (exit 1).
#include <CLI/CLI.hpp>

namespace flexloop::cli {

void register_version(CLI::App& app);
void register_discretise(CLI::App& app);
void register_build(CLI::App& app);
void register_linearise(CLI::App& app);
void register_analyse(CLI::App& app);
void register_baseline(CLI::App& app);
void register_fit_metrology(CLI::App& app);
void register_sim(CLI::App& app);
void register_plant(CLI::App& app);
void register_controller(CLI::App& app);
void register_hil(CLI::App& app);
void register_log(CLI::App& app);
void register_replay(CLI::App& app);
void register_tradeoff(CLI::App& app);
void register_reduce(CLI::App& app);
void register_export_fmu(CLI::App& app);
void register_campaign(CLI::App& app);
/// `campaign worst` (cmd_campaign_worst.cpp), on the campaign command.
void register_campaign_worst(CLI::App* campaign);
void register_roudi(CLI::App& app);

}  // namespace flexloop::cli
