// SPDX-License-Identifier: BSD-3-Clause
// The plant loop on every compiled loop (plant/runtime/compiled_loops.hpp), each with the
// hardware compositions of online/sim/loop_hardware.hpp.
#include "online/loop/plant_loop_run.hpp"

namespace flexloop::loop::detail {

bool run_plant_compiled(const artefact::LoopArtefact& loop, const LoopOptions& o,
                        const std::string& url, PlantLoopResult& r) {
  return plant::runtime::with_compiled_loop(
      plant::runtime::loop_counts(loop),
      [&](auto compiled) {
        using Loop = decltype(compiled);
        sim::with_hardware<Loop::NW, Loop::NC, Loop::NS>(
            loop, plant::runtime::make_compiled_plant<Loop>(loop),
            [&](auto hw) { run_plant_with(std::move(hw), loop, o, url, r); });
        return true;
      },
      [] { return false; });
}

}  // namespace flexloop::loop::detail
