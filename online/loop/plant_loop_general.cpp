// The plant loop on the general path: any state and channel count, sized at start-up, with every
// effect combination (the dense form: the plant process steps what the artefact holds).
#include "online/loop/plant_loop_run.hpp"
#include "plant/runtime/general_plant.hpp"

namespace flexloop::hil::detail {

void run_plant_general(const artefact::LoopArtefact& loop, const LoopOptions& o,
                       const std::string& url, PlantLoopResult& r) {
  constexpr int kAny = Eigen::Dynamic;
  const auto& d = loop.plant;
  const auto plant = plant::runtime::GeneralDensePlant<double>::from_matrices(d.A, d.B, d.C, d.D,
                                                                              loop.actuators());
  sim::with_hardware<kAny, kAny, kAny>(
      loop, plant, [&](auto hw) { run_plant_with(std::move(hw), loop, o, url, r); });
}

}  // namespace flexloop::hil::detail
