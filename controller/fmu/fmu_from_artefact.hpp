// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The FMU alternative of controller/runtime/controller_from_artefact.hpp: a loop artefact's
// controller FMU (artefact/fmu_parameters.hpp) as the runtime runs it, FmuController, from the
// file the artefact names, refused unless its SHA-256 is the one the artefact was built with.
// Only the programs that run a controller FMU include this (and link controller/fmu, with libzip
// and pugixml): sim, the controller process, hil, analyse.
#include "artefact/loop_artefact.hpp"
#include "controller/fmu/fmu_controller.hpp"
#include "controller/runtime/controller_from_artefact.hpp"

namespace flexloop::controller::fmu {

/// The settings that run `a`'s controller FMU: its file, checked against the artefact's SHA-256.
inline FmuControllerSettings fmu_settings(const artefact::LoopArtefact& a) {
  return {a.fmu.file, a.fmu.inputs, a.fmu.outputs, a.fmu.parameters,
          a.dt(),     a.fmu.sha256, a.source,      fmu_archive_limits(a.fmu.max_unpacked_mb)};
}

/// with_controller's Foreign policy that runs a controller FMU.
struct FmuCode {
  static constexpr bool kRuns = true;
  /// @throws flexloop::InputError as FmuController::from_settings (a changed file among them).
  static FmuController make(const artefact::LoopArtefact& a) {
    return FmuController::from_settings(fmu_settings(a));
  }
};

/// with_controller for a program that runs every kind, a controller FMU among them.
template <typename Scalar, int NC = Eigen::Dynamic, int NS = NC, class F>
decltype(auto) with_any_controller(const artefact::LoopArtefact& a, F&& f) {
  return runtime::with_controller<Scalar, NC, NS, FmuCode>(a, std::forward<F>(f));
}

}  // namespace flexloop::controller::fmu
