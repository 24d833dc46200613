// SPDX-License-Identifier: BSD-3-Clause
#include "tools/loop_cli/loop_commands.hpp"

#include <cstdio>
#include <exception>

#include "common/input_error.hpp"
#include "online/loop/run_verdict.hpp"

namespace flexloop::cli {

LoopSource artefact_source() {
  return {"flexloop-", "Loop artefact (JSON, written by flexloop build SCENE -o LOOP.json)",
          "loop.json", [](const std::string& path, const artefact::LoopOverrides& o) {
            return artefact::read_loop_artefact(path, o);
          }};
}

int run_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end with 0; a bad option or value is bad input like a bad file: 2
    // (CLI11's own codes, 105 for a failed check, 109 for an extra argument, say nothing more).
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const loop::VerdictFailure& f) {
    std::fprintf(stderr, "%s: %s\n", f.code == 130 ? "interrupted" : "error", f.message.c_str());
    return f.code;
  } catch (const common::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace flexloop::cli
