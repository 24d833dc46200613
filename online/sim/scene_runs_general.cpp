// SPDX-License-Identifier: BSD-3-Clause
// The general path of `flexloop sim`: any state and channel count, sized at start-up, with the
// effects chosen at start-up (online/sim/loop_hardware.hpp); dense and modal form.
#include "online/sim/run_both.hpp"

namespace flexloop::sim::detail {

BothRuns run_general(const artefact::LoopArtefact& a, const RunSettings& s,
                     const SceneRunOptions& o) {
  constexpr int kAny = Eigen::Dynamic;
  return plant::runtime::with_general_plant<double>(
      a, [&](const auto& plant) { return run_both<kAny, kAny, kAny>(plant, a, s, o); });
}

}  // namespace flexloop::sim::detail
