#pragma once
// The settings that run a loop artefact's controller FMU (artefact/fmu_parameters.hpp).
#include "artefact/loop_artefact.hpp"
#include "controller/fmu/fmu_controller.hpp"

namespace flexloop::controller::fmu {

inline FmuControllerSettings fmu_settings(const artefact::LoopArtefact& a,
                                          FmuFailure* failure_sink = nullptr) {
  return {a.fmu.file, a.fmu.inputs, a.fmu.outputs, a.fmu.parameters, a.dt(), failure_sink};
}

}  // namespace flexloop::controller::fmu
