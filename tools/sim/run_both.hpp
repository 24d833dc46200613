#pragma once
// The body shared by the scene_runs_*.cpp translation units: controller off, then on, over the
// scene's hardware (with every effect, or the floor only).
#include "controller/runtime/pi_controller_sizes.hpp"
#include "plant/runtime/runtime_sizes.hpp"
#include "tools/sim/scene_hardware.hpp"
#include "tools/sim/scene_runs.hpp"

namespace flexloop::sim::detail {

template <int NW, int NC, bool kEffects, class Plant>
BothRuns run_both(const Plant& plant, const std::vector<std::string>& plant_states,
                  const scene::ScenePlant& p, const RunSettings& s, const SceneRunOptions& o) {
  auto ctrl = controller::runtime::PiController<double, NC>::from_parameters(
      pi_parameters_with_hardware(p, s.dt));
  RunSettings off = s, on = s;
  off.log_every = o.log_off ? s.log_every : 0;
  on.log_every = o.log_on ? s.log_every : 0;
  const auto progress = [&o](const char* what) {
    return o.progress ? o.progress(what) : std::function<void(long, long)>{};
  };
  const auto both = [&](auto hw) {
    BothRuns r;
    r.off = run_closed_loop(hw, plant::runtime::NoEffect{}, off, progress("controller off"));
    r.on = run_closed_loop(hw, ctrl, on, progress("controller on"));
    return r;
  };
  if constexpr (kEffects)
    return with_scene_hardware<NW, NC>(p.scene, plant, plant_states, s.dt, both);
  else
    return with_bare_hardware<NW, NC>(p.scene, plant, plant_states, s.dt, both);
}

template <int NX>
BothRuns run_dense_metrology(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                             const RunSettings& s, const SceneRunOptions& o) {
  const auto& d = sampled.plant.sys;
  return run_both<6, 6, true>(
      plant::runtime::DensePlant<double, NX, 12, 12, 6>::from_matrices(d.A, d.B, d.C, d.D),
      d.states, p, s, o);
}

}  // namespace flexloop::sim::detail
