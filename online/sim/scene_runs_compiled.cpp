// SPDX-License-Identifier: BSD-3-Clause
// The compiled fast paths of `flexloop sim`: every entry of the typed list of compiled loops
// (plant/runtime/compiled_loops.hpp), each with the hardware compositions of
// online/sim/loop_hardware.hpp.
#include "online/sim/run_both.hpp"

namespace flexloop::sim::detail {

std::optional<BothRuns> run_compiled(const artefact::LoopArtefact& a, const RunSettings& s,
                                     const SceneRunOptions& o) {
  // A controller sized at start-up (the state-space one): the general path runs it
  // (run_both.hpp).
  if (a.controller != artefact::ControllerKind::kNone &&
      !controller::runtime::has_compiled_kernels(a.controller))
    return std::nullopt;
  return plant::runtime::with_compiled_loop(
      plant::runtime::loop_counts(a),
      [&](auto loop) -> std::optional<BothRuns> {
        using Loop = decltype(loop);
        return run_both<Loop::NW, Loop::NC, Loop::NS>(plant::runtime::make_compiled_plant<Loop>(a),
                                                      a, s, o);
      },
      [] { return std::optional<BothRuns>{}; });
}

}  // namespace flexloop::sim::detail
