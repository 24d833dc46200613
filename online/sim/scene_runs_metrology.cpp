#include "online/sim/run_both.hpp"

namespace flexloop::sim::detail {

BothRuns run_metrology(const artefact::LoopArtefact& a, const RunSettings& s,
                       const SceneRunOptions& o) {
  return run_dense_metrology<12>(a, s, o);
}

}  // namespace flexloop::sim::detail
