// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant and controller processes of the real-time loop as command lines, shared by
// `flexloop plant|controller` (a scene or an artefact: the offline pipeline may run first) and
// the online programs flexloop-plant and flexloop-controller (an artefact only: they link no
// offline code). What differs is the LoopSource: how the positional file becomes the loop.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "artefact/loop_artefact.hpp"

namespace flexloop::cli {

/// How a loop command reads its positional file.
struct LoopSource {
  std::string prefix;   ///< the programs as the user types them, without "plant" or "controller":
                        ///< "flexloop " or "flexloop-"
  std::string help;     ///< what the file may be (the positional's help)
  std::string example;  ///< a file for the --help example
  std::function<artefact::LoopArtefact(const std::string&, const artefact::LoopOverrides&)> load;
};

/// What the online programs take: a loop artefact file (artefact::read_loop_artefact).
LoopSource artefact_source();

/// The positional's help where a scene or an artefact is taken.
inline constexpr const char* kSceneOrArtefactHelp =
    "Scene file (TOML) or loop artefact (JSON, flexloop build)";

/// Options, help and callback of the plant process on `cmd`.
void configure_plant_command(CLI::App* cmd, const LoopSource& source);
/// Options, help and callback of the controller process on `cmd`.
void configure_controller_command(CLI::App* cmd, const LoopSource& source);

/// Parses and runs `app` the way every flexloop program does: exit 0, 2 for bad input
/// (flexloop::InputError, "error: file: ..."), 1 for other failures, CLI11's codes for usage, a
/// real-time run's verdict code (loop::VerdictFailure: 3 fail, 130 interrupted).
int run_command_line(CLI::App& app, int argc, char** argv);

}  // namespace flexloop::cli
