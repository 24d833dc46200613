// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Runs compared sample by sample with a reference that steps from rest (an offline sampled loop,
// another form or order of the same machine) start at rest too (online/sim/loop_start.hpp).
#include "online/sim/scene_runs.hpp"

namespace flexloop::test {

inline sim::SceneRunOptions from_rest() {
  sim::SceneRunOptions o;
  o.start = sim::StartKind::kRest;
  return o;
}

}  // namespace flexloop::test
