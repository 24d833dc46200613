#pragma once
// The body shared by the scene_runs_*.cpp translation units: controller off, then on, over the
// artefact's hardware (with every effect, or the floor only).
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller_sizes.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/runtime/runtime_sizes.hpp"

namespace flexloop::sim::detail {

/// The PI of NC channels: compiled for a compiled NC, start-up-sized for Eigen::Dynamic.
template <int NC>
auto make_pi(const controller::runtime::PiParameters& pi, Eigen::Index channels) {
  if constexpr (NC == Eigen::Dynamic)
    return controller::runtime::GeneralPiController<double>::from_parameters(pi, channels);
  else
    return controller::runtime::PiController<double, NC>::from_parameters(pi);
}

template <int NW, int NC, bool kEffects, class Plant>
BothRuns run_both(const Plant& plant, const artefact::LoopArtefact& a, const RunSettings& s,
                  const SceneRunOptions& o) {
  RunSettings off = s, on = s;
  off.log_every = o.log_off ? s.log_every : 0;
  on.log_every = o.log_on ? s.log_every : 0;
  const auto progress = [&o](const char* what) {
    return o.progress ? o.progress(what) : std::function<void(long, long)>{};
  };
  const bool controlled = a.controller == artefact::ControllerKind::kPiForceFeedback;
  const auto both = [&](auto hw) {
    BothRuns r;
    r.controlled = controlled;
    r.off = run_closed_loop(hw, plant::runtime::NoEffect{}, off, progress("controller off"));
    if (controlled)
      r.on = run_closed_loop(hw, make_pi<NC>(a.pi, a.actuators()), on, progress("controller on"));
    return r;
  };
  // The PI feeds back one sensor per actuator: NS = NC.
  if constexpr (kEffects)
    return with_hardware<NW, NC, NC>(a, plant, both);
  else
    return with_bare_hardware<NW, NC, NC>(a, plant, both);
}

template <int NX>
BothRuns run_dense_metrology(const artefact::LoopArtefact& a, const RunSettings& s,
                             const SceneRunOptions& o) {
  const auto& d = a.plant;
  return run_both<6, 6, true>(
      plant::runtime::DensePlant<double, NX, 12, 12, 6>::from_matrices(d.A, d.B, d.C, d.D), a, s,
      o);
}

}  // namespace flexloop::sim::detail
