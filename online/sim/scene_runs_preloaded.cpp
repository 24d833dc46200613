#include "online/sim/run_both.hpp"

namespace flexloop::sim::detail {

BothRuns run_metrology_preloaded(const artefact::LoopArtefact& a, const RunSettings& s,
                                 const SceneRunOptions& o) {
  return run_dense_metrology<24>(a, s, o);
}

}  // namespace flexloop::sim::detail
