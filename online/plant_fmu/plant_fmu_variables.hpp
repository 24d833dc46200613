// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The variables and log categories of the plant FMU that `flexloop export-fmu` writes (issue 33):
// one list that the exporter's modelDescription.xml and the FMU's own fmi2 functions read, so that
// the two can never disagree on a value reference or a category.
//
//   real inputs   0 .. nc-1                 "actuator.<channel>"     the command held over a step
//   real outputs  nc .. nc+ns-1             "sensor.<channel>"       what the sensors read
//                 nc+ns .. nc+ns+nz-1       "performance.<channel>"  what the performance sensors
//                 read
//   boolean parameter 0                     "start_at_rest"          false: the open loop's
//                                           stationary start (as `flexloop sim`'s controller-off
//                                           run)
#include <cstddef>
#include <iterator>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"

namespace flexloop::plant_fmu {

/// resources/ entries of the plant FMU: the loop artefact it runs and the GUID it was exported
/// with (fmi2Instantiate refuses another).
inline constexpr const char* kArtefactResource = "loop.json";
inline constexpr const char* kGuidResource = "guid.txt";
/// The shared library's name: binaries/linux64/<kModelIdentifier>.so.
inline constexpr const char* kModelIdentifier = "flexloop_plant";
inline constexpr unsigned kStartAtRestReference = 0;  ///< the one boolean parameter

struct PlantFmuVariable {
  std::string name;
  unsigned value_reference;
  bool input;        ///< else an output
  std::string unit;  ///< the artefact's channel unit, e.g. "m/s^2", "N"
};

/// The log categories modelDescription.xml declares, each one the FMU logs under
/// (fmi2SetDebugLogging names them).
struct PlantFmuLogCategory {
  const char* name;
  const char* description;
};
inline constexpr PlantFmuLogCategory kLogCategories[] = {
    {"logStatusError",
     "why a call returned fmi2Error (on from fmi2Instantiate, whatever its loggingOn)"},
    {"logEvents",
     "the instance's changes of state: instantiated, initialised, terminated, reset (on when "
     "fmi2Instantiate's loggingOn is true)"},
};
inline constexpr std::size_t kLogStatusError = 0, kLogEvents = 1;
inline constexpr std::size_t kLogCategoryCount = std::size(kLogCategories);

/// The real variables of the artefact's plant FMU, by value reference.
inline std::vector<PlantFmuVariable> plant_fmu_variables(const artefact::LoopArtefact& a) {
  std::vector<PlantFmuVariable> v;
  unsigned vr = 0;
  for (const auto& c : a.channels.actuators)
    v.push_back({"actuator." + c.name, vr++, true, c.unit});
  for (const auto& c : a.channels.sensors) v.push_back({"sensor." + c.name, vr++, false, c.unit});
  for (const auto& c : a.channels.performance)
    v.push_back({"performance." + c.name, vr++, false, c.unit});
  return v;
}

}  // namespace flexloop::plant_fmu
