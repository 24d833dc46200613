// The plant loop for the gravity-preloaded metrology frame (24 states) with every effect
// combination.
#include "online/loop/plant_loop_run.hpp"

namespace flexloop::hil::detail {

void run_plant_preloaded(const artefact::LoopArtefact& loop, const LoopOptions& o,
                         const std::string& url, PlantLoopResult& r) {
  run_plant_of_size<24>(loop, o, url, r);
}

}  // namespace flexloop::hil::detail
