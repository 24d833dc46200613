#pragma once
// The body shared by the scene_runs_*.cpp translation units: controller off, then on, over the
// artefact's hardware with every effect it carries.
#include <string>

#include "common/input_error.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/scene_runs.hpp"

namespace flexloop::sim::detail {

/// The PI of NC channels: compiled for a compiled NC, start-up-sized for Eigen::Dynamic.
template <int NC>
auto make_pi(const controller::runtime::PiParameters& pi, Eigen::Index channels) {
  if constexpr (NC == Eigen::Dynamic)
    return controller::runtime::GeneralPiController<double>::from_parameters(pi, channels);
  else
    return controller::runtime::PiController<double, NC>::from_parameters(pi);
}

/// NW disturbances, NC actuators, NS sensors: compiled counts, or Eigen::Dynamic.
template <int NW, int NC, int NS, class Plant>
BothRuns run_both(const Plant& plant, const artefact::LoopArtefact& a, const RunSettings& s,
                  const SceneRunOptions& o) {
  RunSettings off = s, on = s;
  off.log_every = o.log_off ? s.log_every : 0;
  on.log_every = o.log_on ? s.log_every : 0;
  const auto progress = [&o](const char* what) {
    return o.progress ? o.progress(what) : std::function<void(long, long)>{};
  };
  const bool controlled = a.controller == artefact::ControllerKind::kPiForceFeedback;
  // The PI feeds back one sensor per actuator (the artefact's validation holds NS = NC already).
  if constexpr (NS != NC)
    if (controlled)
      throw InputError(a.source,
                       "[controller]: the PI force feedback needs one sensor per "
                       "actuator; this loop has " +
                           std::to_string(a.sensors()) + " sensors and " +
                           std::to_string(a.actuators()) + " actuators");
  return with_hardware<NW, NC, NS>(a, plant, [&](auto hw) {
    BothRuns r;
    r.controlled = controlled;
    r.off = run_closed_loop(hw, plant::runtime::NoEffect{}, off, progress("controller off"));
    if constexpr (NS == NC)
      if (controlled)
        r.on = run_closed_loop(hw, make_pi<NC>(a.pi, a.actuators()), on, progress("controller on"));
    return r;
  });
}

}  // namespace flexloop::sim::detail
