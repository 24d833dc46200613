#pragma once
// The body shared by the scene_runs_*.cpp translation units: controller off, then on, over the
// artefact's hardware with every effect it carries. The PI runs on compiled and general paths;
// the state-space controller, sized at start-up, on the general path only (one more
// instantiation of every hardware composition per compiled loop, for a step that the
// controller's own products dominate).
#include <stdexcept>
#include <string>

#include "common/input_error.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "controller/runtime/state_space_controller.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/scene_runs.hpp"

namespace flexloop::sim::detail {

/// The PI of NC channels: compiled for a compiled NC, start-up-sized for Eigen::Dynamic.
template <int NC>
auto make_pi(const artefact::PiParameters& pi, Eigen::Index channels) {
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
  using artefact::ControllerKind;
  const bool pi = a.controller == ControllerKind::kPiForceFeedback,
             state_space = a.controller == ControllerKind::kStateSpace;
  // The PI feeds back one sensor per actuator (the artefact's validation holds NS = NC already).
  if constexpr (NS != NC)
    if (pi)
      throw common::InputError(a.source,
                               "[controller]: the PI force feedback needs one sensor per "
                               "actuator; this loop has " +
                                   std::to_string(a.sensors()) + " sensors and " +
                                   std::to_string(a.actuators()) + " actuators");
  // The state-space controller is start-up-sized: it runs with the general path's hardware
  // (run_compiled leaves it to run_general).
  constexpr bool kGeneral = NW == Eigen::Dynamic && NC == Eigen::Dynamic && NS == Eigen::Dynamic;
  if (state_space && !kGeneral)
    throw std::logic_error("run_both: a state-space controller runs on the general path");
  return with_hardware<NW, NC, NS>(a, plant, [&](auto hw) {
    BothRuns r;
    r.controlled = pi || state_space;
    r.start_off = describe_start(o.start, a.start.open_loop, "open loop");
    if (r.controlled) r.start_on = describe_start(o.start, a.start.closed_loop, "closed loop");
    // Each run from the same seeds, started in its own loop's stationary state.
    const auto run_started = [&](auto controller, const artefact::StationaryStart& start,
                                 const RunSettings& settings, const char* what) {
      auto started = hw;
      start_loop(a, start, o.start, started, controller);
      return run_closed_loop(std::move(started), std::move(controller), settings, progress(what));
    };
    const auto run_off = [&] {
      r.off = run_started(plant::runtime::NoEffect{}, a.start.open_loop, off, "controller off");
    };
    const auto run_on = [&] {
      if constexpr (NS == NC)
        if (pi)
          r.on = run_started(make_pi<NC>(a.pi, a.actuators()), a.start.closed_loop, on,
                             "controller on");
      if constexpr (kGeneral)
        if (state_space)
          r.on = run_started(
              controller::runtime::StateSpaceController<double>::from_parameters(a.state_space),
              a.start.closed_loop, on, "controller on");
    };
    const bool on_first = o.on_first && r.controlled;
    if (on_first) {
      run_on();
      if (o.after_first_run) o.after_first_run(r.on);
      run_off();
    } else {
      run_off();
      if (o.after_first_run) o.after_first_run(r.off);
      run_on();
    }
    return r;
  });
}

}  // namespace flexloop::sim::detail
