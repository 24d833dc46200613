#include "tools/sim/scene_runs.hpp"

#include "plant/lti/modal_form.hpp"
#include "plant/model/input_error.hpp"
#include "plant/runtime/runtime_sizes.hpp"
#include "tools/sim/run_both.hpp"

namespace flexloop::sim {

namespace detail {

// Every compiled size: the actuator count is half the inputs (6 floor + 6 piezo for the
// metrology frame, 1 + 1 for the cart). The floor only, dense or modal.
BothRuns run_bare(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                  const RunSettings& s, const SceneRunOptions& o) {
  const auto& d = sampled.plant.sys;
  return plant::runtime::with_runtime_size(d.nx(), d.nu(), d.ny(), [&](auto size) -> BothRuns {
    using Size = decltype(size);
    constexpr int NC = Size::NH, NW = Size::NU - NC;
    if constexpr (NC < 1 || Size::NY <= NC) {
      throw InputError(p.scene.file, "[plant]: no compiled loop for these channel counts");
    } else {
      if (o.form == "modal")
        return run_both<NW, NC, false>(
            plant::runtime::ModalPlant<double, Size::NX, Size::NU, Size::NY, NC>::from_modal_form(
                plant::lti::to_modal_form(sampled.plant)),
            d.states, p, s, o);
      return run_both<NW, NC, false>(
          plant::runtime::DensePlant<double, Size::NX, Size::NU, Size::NY, NC>::from_matrices(
              d.A, d.B, d.C, d.D),
          d.states, p, s, o);
    }
  });
}

}  // namespace detail

BothRuns run_scene(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                   const RunSettings& s, const SceneRunOptions& o) {
  const auto& d = sampled.plant.sys;
  const long nc = static_cast<long>(p.scene.actuators.size()),
             nw = static_cast<long>(p.scene.disturbances.size());
  if (2 * nc != d.nu() || nw != nc)
    throw InputError(p.scene.file,
                     "[plant]: the runtime's loops expect as many disturbances as "
                     "actuators (the scene has " +
                         std::to_string(nw) + " and " + std::to_string(nc) + ")");
  const bool metrology_io = d.nu() == 12 && d.ny() == 12 && o.form == "dense";
  if (metrology_io && d.nx() == 12) return detail::run_metrology(p, sampled, s, o);
  if (metrology_io && d.nx() == 24) return detail::run_metrology_preloaded(p, sampled, s, o);
  return detail::run_bare(p, sampled, s, o);
}

}  // namespace flexloop::sim
