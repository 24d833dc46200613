#pragma once
// The controller of a loop artefact as the controller process runs it: the PI force feedback,
// compiled for the metrology frame's 6 channels, sized at start-up for any other count.
#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller_sizes.hpp"
#include "online/loop/plant_station.hpp"

namespace flexloop::hil {

/// The metrology frame's loop controller (6 channels). @throws std::invalid_argument for another
/// channel count.
inline controller::runtime::PiController<double, kChannels> make_loop_controller(
    const artefact::LoopArtefact& a) {
  return controller::runtime::PiController<double, kChannels>::from_parameters(a.pi);
}

/// f(controller) for the artefact's controller.
/// @throws flexloop::InputError naming the artefact when it has no controller to run.
template <class F>
decltype(auto) with_loop_controller(const artefact::LoopArtefact& a, F&& f) {
  if (a.controller != artefact::ControllerKind::kPiForceFeedback)
    throw InputError(a.source, "key 'controller': the loop has no controller to run (type \"" +
                                   artefact::to_string(a.controller) +
                                   "\"); run your own controller process against `flexloop plant`");
  if (a.actuators() == kChannels) return f(make_loop_controller(a));
  return f(controller::runtime::GeneralPiController<double>::from_parameters(a.pi, a.actuators()));
}

}  // namespace flexloop::hil
