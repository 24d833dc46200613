#pragma once
// Part of the loop artefact's schema: a controller FMU's start-up parameters (issue 33): the FMI
// 2.0 Co-Simulation FMU the loop runs (controller/fmu), the SHA-256 of the file that was built
// into the artefact, the parameters the scene sets, and the FMU's real variables the loop
// connects, in the channel map's order.
#include <string>
#include <utility>
#include <vector>

namespace flexloop::artefact {

struct FmuParameters {
  std::string file;    ///< absolute path of the .fmu
  std::string sha256;  ///< of the file when the artefact was built (lower-case hex)
  std::vector<std::pair<std::string, double>> parameters;  ///< real parameters, set at start-up
  std::vector<std::string> inputs;                         ///< the FMU's real input for each sensor
  std::vector<std::string> outputs;  ///< the FMU's real output for each actuator
};

}  // namespace flexloop::artefact
