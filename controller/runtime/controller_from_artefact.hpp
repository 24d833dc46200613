// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// From a loop artefact's controller (artefact/loop_artefact.hpp) to the runtime controller that
// runs it (loop_controller.hpp): the one place `flexloop sim`, the controller process and the
// tradeoff study build it, and the one place that refuses an artefact whose controller cannot
// run. Each kind is one case of with_controller:
//
//   kPiForceFeedback  the PI force feedback: PiController<Scalar, NC> on the fixed-size kernels
//                     of NC channels, or GeneralPiController<Scalar>, sized at start-up
//   kStateSpace       the user's StateSpaceController<Scalar>, sized at start-up
//   kFmu              the user's compiled controller: foreign code, which this header does not
//                     load (controller/runtime links no FMU loader, libzip or pugixml). A caller
//                     that runs it names how as the Foreign policy, controller/fmu's FmuCode
//                     (controller/fmu/fmu_from_artefact.hpp: FmuController, double only, sized at
//                     start-up); with NoForeignCode, the default, the artefact is refused.
//
// Which channel counts run on fixed-size kernels is the caller's to say (the compiled loops of
// plant/runtime/compiled_loops.hpp, which the controller does not see): it asks with compiled
// counts only for a kind that has_compiled_kernels, and with Eigen::Dynamic otherwise. A new kind
// sized at start-up is one more case in with_controller's switch (the compiler asks for it).
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "controller/runtime/state_space_controller.hpp"

namespace flexloop::controller::runtime {

/// The Foreign policy of a caller that runs only flexloop's own kernels: a controller FMU is
/// refused. A policy that runs foreign code has kRuns = true and make(artefact), which returns
/// the controller (a LoopController sized at start-up, in double).
struct NoForeignCode {
  static constexpr bool kRuns = false;
};

/// True for a kind with fixed-size kernels (the PI force feedback), which with_controller builds
/// for compiled channel counts; every other kind runs sized at start-up.
constexpr bool has_compiled_kernels(artefact::ControllerKind kind) {
  return kind == artefact::ControllerKind::kPiForceFeedback;
}

/// f(controller) for the artefact's controller, in Scalar, for a loop of NC actuators and NS
/// sensors: compiled counts (the fixed-size kernels of a kind that has_compiled_kernels), or
/// Eigen::Dynamic (sized at start-up, every kind). Returns what f returns (the same type for
/// every kind).
/// @throws flexloop::InputError naming the artefact when it has no controller to run, or when
/// its PI force feedback does not have one sensor per actuator.
/// @throws std::invalid_argument as the controller's from_parameters, for parameters it refuses.
/// @throws std::logic_error for compiled counts with a kind sized at start-up (the caller's
/// dispatch is wrong), or a controller FMU in float.
/// Foreign: how a controller FMU runs (NoForeignCode: it is refused with flexloop::InputError
/// and f is never instantiated for it); see NoForeignCode. Whatever the controller reports of its
/// run (loop_controller.hpp: report()) f asks it, after the run.
template <typename Scalar, int NC = Eigen::Dynamic, int NS = NC, class Foreign = NoForeignCode,
          class F>
decltype(auto) with_controller(const artefact::LoopArtefact& a, F&& f) {
  using artefact::ControllerKind;
  constexpr bool kSizedAtStartUp = NC == Eigen::Dynamic && NS == Eigen::Dynamic;
  switch (a.controller) {
    case ControllerKind::kNone:
      throw common::InputError(a.source,
                               "key 'controller': the loop has no controller to run (type \"" +
                                   artefact::to_string(a.controller) +
                                   "\"); run your own controller process against `flexloop "
                                   "plant` (doc/external_controller.md)");
    case ControllerKind::kPiForceFeedback:
      if constexpr (NC == NS)
        if (a.sensors() == a.actuators()) {
          if constexpr (kSizedAtStartUp)
            return f(GeneralPiController<Scalar>::from_parameters(a.pi, a.actuators()));
          else
            return f(PiController<Scalar, NC>::from_parameters(a.pi));
        }
      throw common::InputError(a.source,
                               "[controller]: the PI force feedback needs one sensor per "
                               "actuator; this loop has " +
                                   std::to_string(a.sensors()) + " sensors and " +
                                   std::to_string(a.actuators()) + " actuators");
    case ControllerKind::kStateSpace:
      if constexpr (kSizedAtStartUp)
        return f(StateSpaceController<Scalar>::from_parameters(a.state_space));
      break;
    case ControllerKind::kFmu:
      if constexpr (!Foreign::kRuns)
        throw common::InputError(a.source,
                                 "[controller]: a controller FMU is foreign code, which this "
                                 "command does not load; it runs in flexloop sim, hil, analyse "
                                 "and the controller process");
      else if constexpr (kSizedAtStartUp && std::is_same_v<Scalar, double>)
        return f(Foreign::make(a));
      break;
  }
  throw std::logic_error("with_controller: the controller \"" + artefact::to_string(a.controller) +
                         "\" is sized at start-up (NC = NS = Eigen::Dynamic)");
}

}  // namespace flexloop::controller::runtime
