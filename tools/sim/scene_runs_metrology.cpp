#include "tools/sim/run_both.hpp"

namespace flexloop::sim::detail {

BothRuns run_metrology(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                       const RunSettings& s, const SceneRunOptions& o) {
  return run_dense_metrology<12>(p, sampled, s, o);
}

}  // namespace flexloop::sim::detail
