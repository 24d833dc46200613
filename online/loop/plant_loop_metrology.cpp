// The plant loop for the metrology frame (12 states) with every effect combination.
#include "online/loop/plant_loop_run.hpp"

namespace flexloop::hil::detail {

void run_plant_metrology(const artefact::LoopArtefact& loop, const LoopOptions& o,
                         const std::string& url, PlantLoopResult& r) {
  run_plant_of_size<12>(loop, o, url, r);
}

}  // namespace flexloop::hil::detail
