#pragma once
// The controller of a loop artefact as the controller process runs it: the PI force feedback, on
// the fixed-size kernels where the loop's channel counts have a compiled loop
// (plant/runtime/compiled_loops.hpp), sized at start-up for any other count; or the user's
// state-space controller, sized at start-up.
#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "controller/runtime/state_space_controller.hpp"
#include "plant/runtime/compiled_loops.hpp"

namespace flexloop::loop {

/// f(controller) for the artefact's controller (controller/runtime/loop_controller.hpp).
/// @throws flexloop::InputError naming the artefact when it has no controller to run.
template <class F>
decltype(auto) with_loop_controller(const artefact::LoopArtefact& a, F&& f) {
  using artefact::ControllerKind;
  if (a.controller == ControllerKind::kNone)
    throw common::InputError(a.source,
                             "key 'controller': the loop has no controller to run (type \"" +
                                 artefact::to_string(a.controller) +
                                 "\"); run your own controller process against `flexloop "
                                 "plant` (doc/external_controller.md)");
  if (a.controller == ControllerKind::kStateSpace)
    return f(controller::runtime::StateSpaceController<double>::from_parameters(a.state_space));
  return plant::runtime::with_compiled_channels(
      a.actuators(), a.sensors(),
      [&](auto loop) -> decltype(auto) {
        return f(
            controller::runtime::PiController<double, decltype(loop)::NC>::from_parameters(a.pi));
      },
      [&]() -> decltype(auto) {
        return f(
            controller::runtime::GeneralPiController<double>::from_parameters(a.pi, a.actuators()));
      });
}

}  // namespace flexloop::loop
