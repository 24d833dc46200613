// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The body shared by the scene_runs_*.cpp translation units: controller off, then on, over the
// artefact's hardware with every effect it carries. The controller is the artefact's
// (controller/runtime/controller_from_artefact.hpp): the PI runs on compiled and general paths;
// the state-space controller and a controller FMU, sized at start-up, on the general path only (one
// more instantiation of every hardware composition per compiled loop, for a step that the
// controller's own products dominate). A controller FMU's refusal (fmi2Error, fmi2Fatal) is an
// input error here; a run it could not complete (fmi2Discard, fmi2Pending) is in on.controller,
// for the caller to judge (sim fails, hil reports it beside its own run).
#include "common/input_error.hpp"
#include "controller/fmu/fmu_from_artefact.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/scene_runs.hpp"
#include "plant/runtime/plant_from_artefact.hpp"

namespace flexloop::sim::detail {

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
  return with_hardware<NW, NC, NS>(a, plant, [&](auto hw) {
    BothRuns r;
    r.controlled = a.controller != artefact::ControllerKind::kNone;
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
    // The controller of a compiled loop has its channel counts (run_compiled leaves a kind
    // sized at start-up to run_general).
    const auto run_on = [&] {
      if (!r.controlled) return;
      controller::fmu::with_any_controller<double, NC, NS>(a, [&](auto controller) {
        r.on = run_started(std::move(controller), a.start.closed_loop, on, "controller on");
      });
      if (r.on.controller.refused)
        throw common::InputError(
            a.fmu.file,
            r.on.controller.failure + "; the controller-on run stopped commanding there");
    };
    const bool on_first = o.on_first && r.controlled;
    if (o.on_only && r.controlled) {
      run_on();
      if (o.after_first_run) o.after_first_run(r.on);
    } else if (on_first) {
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
