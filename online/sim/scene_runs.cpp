// SPDX-License-Identifier: BSD-3-Clause
#include "online/sim/scene_runs.hpp"

#include <utility>

namespace flexloop::sim {

BothRuns run_artefact(const artefact::LoopArtefact& a, const RunSettings& s,
                      const SceneRunOptions& o) {
  if (!o.general)
    if (auto compiled = detail::run_compiled(a, s, o)) return *std::move(compiled);
  return detail::run_general(a, s, o);
}

}  // namespace flexloop::sim
