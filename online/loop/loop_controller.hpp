// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The controller of a loop artefact as the controller process runs it
// (controller/runtime/controller_from_artefact.hpp builds it): on the fixed-size kernels where the
// loop's channel counts have a compiled loop (plant/runtime/compiled_loops.hpp) and the kind has
// them, sized at start-up otherwise.
#include "artefact/loop_artefact.hpp"
#include "controller/fmu/fmu_from_artefact.hpp"
#include "plant/runtime/compiled_loops.hpp"

namespace flexloop::loop {

/// f(controller) for the artefact's controller (controller/runtime/loop_controller.hpp).
/// @throws flexloop::InputError naming the artefact when it has no controller to run, and as
/// controller::runtime::with_controller.
template <class F>
decltype(auto) with_loop_controller(const artefact::LoopArtefact& a, F&& f) {
  using controller::fmu::with_any_controller;
  if (!controller::runtime::has_compiled_kernels(a.controller))
    return with_any_controller<double>(a, f);
  return plant::runtime::with_compiled_channels(
      a.actuators(), a.sensors(),
      [&](auto loop) -> decltype(auto) {
        using Loop = decltype(loop);
        return with_any_controller<double, Loop::NC, Loop::NS>(a, f);
      },
      [&]() -> decltype(auto) { return with_any_controller<double>(a, f); });
}

}  // namespace flexloop::loop
