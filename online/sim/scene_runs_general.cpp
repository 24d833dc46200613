// The general path of `flexloop sim`: any state and channel count, sized at start-up, with the
// effects chosen at start-up (online/sim/loop_hardware.hpp); dense and modal form.
#include "online/sim/run_both.hpp"
#include "plant/runtime/general_plant.hpp"

namespace flexloop::sim::detail {

BothRuns run_general(const artefact::LoopArtefact& a, const RunSettings& s,
                     const SceneRunOptions& o) {
  constexpr int kAny = Eigen::Dynamic;
  const auto& d = a.plant;
  if (d.form == artefact::PlantForm::kModal)
    return run_both<kAny, kAny, kAny>(
        plant::runtime::GeneralModalPlant<double>::from_modal_form(d.modal, a.actuators()), a, s,
        o);
  return run_both<kAny, kAny, kAny>(
      plant::runtime::GeneralDensePlant<double>::from_matrices(d.A, d.B, d.C, d.D, a.actuators()),
      a, s, o);
}

}  // namespace flexloop::sim::detail
