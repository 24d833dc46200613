#pragma once
// `flexloop sim`'s runs of a scene: the same floor and hardware (same seeds) once with the
// controller off and once on. The compiled combinations of plant size, form and effects live in
// separate translation units (scene_runs_*.cpp) so that they build in parallel.
#include <functional>
#include <string>

#include "tools/scene/scene_plant.hpp"
#include "tools/sim/closed_loop_run.hpp"

namespace flexloop::sim {

struct BothRuns {
  RunResult off, on;
};

using ProgressFactory = std::function<std::function<void(long, long)>(const char* what)>;

struct SceneRunOptions {
  std::string form = "dense";  ///< dense | modal
  bool log_off = false, log_on = false;
  ProgressFactory progress;
};

/// @throws flexloop::InputError naming the scene for sizes or effects this build has no loop for.
BothRuns run_scene(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                   const RunSettings& s, const SceneRunOptions& o);

namespace detail {
// One per translation unit: the dense metrology plant (12 states) and its gravity-preloaded
// variant (24 states) with every effect combination; everything else with the floor only.
BothRuns run_metrology(const scene::ScenePlant&, const scene::SampledScene&, const RunSettings&,
                       const SceneRunOptions&);
BothRuns run_metrology_preloaded(const scene::ScenePlant&, const scene::SampledScene&,
                                 const RunSettings&, const SceneRunOptions&);
BothRuns run_bare(const scene::ScenePlant&, const scene::SampledScene&, const RunSettings&,
                  const SceneRunOptions&);
}  // namespace detail

}  // namespace flexloop::sim
