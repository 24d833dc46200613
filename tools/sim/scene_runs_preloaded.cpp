#include "tools/sim/run_both.hpp"

namespace flexloop::sim::detail {

BothRuns run_metrology_preloaded(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                                 const RunSettings& s, const SceneRunOptions& o) {
  return run_dense_metrology<24>(p, sampled, s, o);
}

}  // namespace flexloop::sim::detail
