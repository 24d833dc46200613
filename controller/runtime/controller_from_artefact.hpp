#pragma once
// From a loop artefact's controller (artefact/loop_artefact.hpp) to the runtime controller that
// runs it (loop_controller.hpp): the one place `flexloop sim`, the controller process and the
// tradeoff study build it, and the one place that refuses an artefact whose controller cannot
// run. Each kind is one case of with_controller:
//
//   kPiForceFeedback  the PI force feedback: PiController<Scalar, NC> on the fixed-size kernels
//                     of NC channels, or GeneralPiController<Scalar>, sized at start-up
//   kStateSpace       the user's StateSpaceController<Scalar>, sized at start-up
//   kFmu              the user's compiled controller, controller::fmu::FmuController (double
//                     only: the FMI's fmi2Real), sized at start-up
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
#include "controller/fmu/fmu_artefact_settings.hpp"
#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "controller/runtime/state_space_controller.hpp"

namespace flexloop::controller::runtime {

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
/// fmu_failure: where a controller FMU records a call that fails in the loop (the run consumes
/// the controller; the caller asks afterwards). Optional.
/// kForeignCode false: a caller that runs only flexloop's own kernels (the trade-off study);
/// a controller FMU is then refused (flexloop::InputError) and f is never instantiated for it.
template <typename Scalar, int NC = Eigen::Dynamic, int NS = NC, bool kForeignCode = true, class F>
decltype(auto) with_controller(const artefact::LoopArtefact& a, F&& f,
                               fmu::FmuFailure* fmu_failure = nullptr) {
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
      if constexpr (!kForeignCode)
        throw common::InputError(a.source,
                                 "[controller]: a controller FMU is foreign code; this command "
                                 "compares flexloop's own kernels (run the FMU with flexloop sim)");
      else if constexpr (kSizedAtStartUp && std::is_same_v<Scalar, double>)
        return f(fmu::FmuController::from_settings(fmu::fmu_settings(a, fmu_failure)));
      break;
  }
  throw std::logic_error("with_controller: the controller \"" + artefact::to_string(a.controller) +
                         "\" is sized at start-up (NC = NS = Eigen::Dynamic)");
}

}  // namespace flexloop::controller::runtime
