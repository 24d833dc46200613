// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `flexloop export-fmu`: a loop artefact's plant, simulated hardware and floor as an FMI 2.0
// Co-Simulation FMU (issue 33) for a user's own simulation tool. The archive holds
//   modelDescription.xml                    the variables and log categories of
//                                           online/plant_fmu/plant_fmu_variables.hpp with their
//                                           SI units, the loop period as the fixed stepSize, a
//                                           GUID that is the SHA-256 of the artefact's JSON
//   binaries/linux64/flexloop_plant.so      the project's plant FMU library (online/plant_fmu)
//   resources/loop.json, resources/guid.txt the artefact the library runs, and its GUID
#include <filesystem>

#include "artefact/loop_artefact.hpp"

namespace flexloop::pipeline {

/// Writes `fmu` atomically (a temporary file beside it, renamed when complete: nothing
/// half-written on failure). `library`: the built flexloop_plant.so. @throws
/// flexloop::common::InputError naming the file that cannot be read or written.
void export_plant_fmu(const artefact::LoopArtefact& a, const std::filesystem::path& library,
                      const std::filesystem::path& fmu);

/// The modelDescription.xml of `a`'s plant FMU with `guid`: FMI 2.0 (the schema of
/// tests/fixtures/fmi2_schema), every real variable with the SI unit of its channel
/// (<UnitDefinitions>, si_unit.hpp), the log categories the FMU logs under. @throws
/// flexloop::InputError naming the artefact and the channel whose unit does not read.
std::string plant_fmu_description(const artefact::LoopArtefact& a, const std::string& guid);

}  // namespace flexloop::pipeline
