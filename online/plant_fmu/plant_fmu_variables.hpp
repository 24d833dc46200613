#pragma once
// The variables of the plant FMU that `flexloop export-fmu` writes (issue 33): one list that the
// exporter's modelDescription.xml and the FMU's own fmi2GetReal / fmi2SetReal read, so that the
// two can never disagree on a value reference.
//
//   real inputs   0 .. nc-1                 "actuator.<channel>"     the command held over a step
//   real outputs  nc .. nc+ns-1             "sensor.<channel>"       what the sensors read
//                 nc+ns .. nc+ns+nz-1       "performance.<channel>"  what the performance sensors
//                 read
//   boolean parameter 0                     "start_at_rest"          false: the open loop's
//                                           stationary start (as `flexloop sim`'s controller-off
//                                           run)
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
  bool input;  ///< else an output
};

/// The real variables of the artefact's plant FMU, by value reference.
inline std::vector<PlantFmuVariable> plant_fmu_variables(const artefact::LoopArtefact& a) {
  std::vector<PlantFmuVariable> v;
  unsigned vr = 0;
  for (const auto& name : a.names(a.channels.actuators))
    v.push_back({"actuator." + name, vr++, true});
  for (const auto& name : a.names(a.channels.sensors)) v.push_back({"sensor." + name, vr++, false});
  for (const auto& name : a.names(a.channels.performance))
    v.push_back({"performance." + name, vr++, false});
  return v;
}

}  // namespace flexloop::plant_fmu
