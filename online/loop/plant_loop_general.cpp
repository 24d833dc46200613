// SPDX-License-Identifier: BSD-3-Clause
// The plant loop on the general path: any state and channel count, sized at start-up, with the
// effects chosen at start-up (online/sim/loop_hardware.hpp), in the plant form the artefact holds.
#include "online/loop/plant_loop_run.hpp"

namespace flexloop::loop::detail {

void run_plant_general(const artefact::LoopArtefact& loop, const LoopOptions& o,
                       const std::string& url, PlantLoopResult& r) {
  constexpr int kAny = Eigen::Dynamic;
  plant::runtime::with_general_plant<double>(loop, [&](const auto& plant) {
    sim::with_hardware<kAny, kAny, kAny>(
        loop, plant, [&](auto hw) { run_plant_with(std::move(hw), loop, o, url, r); });
  });
}

}  // namespace flexloop::loop::detail
