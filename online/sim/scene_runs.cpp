#include "online/sim/scene_runs.hpp"

#include "online/sim/run_both.hpp"
#include "plant/runtime/runtime_sizes.hpp"

namespace flexloop::sim {

namespace detail {

// Every compiled size: the actuator count is half the inputs (6 floor + 6 piezo for the
// metrology frame, 1 + 1 for the cart). The floor only, dense or modal.
BothRuns run_bare(const artefact::LoopArtefact& a, const RunSettings& s, const SceneRunOptions& o) {
  const auto& d = a.plant;
  return plant::runtime::with_runtime_size(
      d.A.rows(), d.B.cols(), d.C.rows(), [&](auto size) -> BothRuns {
        using Size = decltype(size);
        constexpr int NC = Size::NH, NW = Size::NU - NC;
        if constexpr (NC < 1 || Size::NY <= NC) {
          throw InputError(a.source, "[plant]: no compiled loop for these channel counts");
        } else {
          if (d.form == "modal")
            return run_both<NW, NC, false>(
                plant::runtime::ModalPlant<double, Size::NX, Size::NU, Size::NY,
                                           NC>::from_modal_form(d.modal),
                a, s, o);
          return run_both<NW, NC, false>(
              plant::runtime::DensePlant<double, Size::NX, Size::NU, Size::NY, NC>::from_matrices(
                  d.A, d.B, d.C, d.D),
              a, s, o);
        }
      });
}

}  // namespace detail

BothRuns run_artefact(const artefact::LoopArtefact& a, const RunSettings& s,
                      const SceneRunOptions& o) {
  const auto& d = a.plant;
  const Eigen::Index nw = a.disturbances(), nc = a.actuators(), nz = a.performance(),
                     ns = a.sensors();
  // The compiled paths: as many disturbances as actuators, one sensor per actuator.
  const bool compiled_counts = !o.general && nw == nc && ns == nc;
  const bool metrology_io = compiled_counts && nc == 6 && nz == 6 && d.form == "dense";
  if (metrology_io && d.A.rows() == 12) return detail::run_metrology(a, s, o);
  if (metrology_io && d.A.rows() == 24) return detail::run_metrology_preloaded(a, s, o);
  const bool compiled_size = plant::runtime::with_runtime_size(
      d.A.rows(), d.B.cols(), d.C.rows(), [](auto) { return true; }, [] { return false; });
  if (compiled_counts && compiled_size && !has_effects(a.effects)) return detail::run_bare(a, s, o);
  return detail::run_general(a, s, o);
}

}  // namespace flexloop::sim
