// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `flexloop sim`'s runs of a loop artefact: the same floor and hardware (same seeds) once with the
// controller off and once on (a loop without a controller runs once). An artefact whose counts
// and form have a compiled fast path (plant/runtime/compiled_loops.hpp) runs on it; every other
// one runs on the general path, sized at start-up. The compiled loops and the general path live
// in separate translation units (scene_runs_*.cpp) so that they build in parallel.
#include <functional>
#include <optional>
#include <string>

#include "artefact/loop_artefact.hpp"
#include "online/sim/closed_loop_run.hpp"
#include "online/sim/loop_start.hpp"

namespace flexloop::sim {

struct BothRuns {
  RunResult off, on;
  bool controlled = true;  ///< false: the artefact has no controller, `on` is not run
  /// How each run started (online/sim/loop_start.hpp: describe_start).
  std::string start_off, start_on;
};

using ProgressFactory = std::function<std::function<void(long, long)>(const char* what)>;

struct SceneRunOptions {
  /// Run on the start-up-sized general path even where a compiled loop matches (comparisons).
  bool general = false;
  /// Each run starts in a draw from its loop's stationary distribution (artefact/loop_start.hpp)
  /// where the loop has one, or at rest.
  StartKind start = StartKind::kStationary;
  bool log_off = false, log_on = false;
  ProgressFactory progress;
  /// Run the controller-on run first (the off run first otherwise, and always without a
  /// controller). The same results in either order: both runs start from the same seeds.
  bool on_first = false;
  /// Run the controller-on run alone (`off` stays empty): a campaign's sample judges only the
  /// closed loop, and the open-loop run would double its cost.
  bool on_only = false;
  /// Called with the first run's result as soon as it ends, before the second starts: a caller
  /// may take its log and write it while the second run goes on.
  std::function<void(RunResult&)> after_first_run;
};

/// @throws flexloop::InputError naming the artefact for what its hardware refuses.
BothRuns run_artefact(const artefact::LoopArtefact& a, const RunSettings& s,
                      const SceneRunOptions& o);

namespace detail {
// One per translation unit: the compiled loop that matches the artefact (nothing when none does),
// and the general path; each with the hardware compositions of online/sim/loop_hardware.hpp.
std::optional<BothRuns> run_compiled(const artefact::LoopArtefact&, const RunSettings&,
                                     const SceneRunOptions&);
BothRuns run_general(const artefact::LoopArtefact&, const RunSettings&, const SceneRunOptions&);
}  // namespace detail

}  // namespace flexloop::sim
