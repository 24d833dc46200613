#pragma once
// An FMI 2.0 Co-Simulation FMU's modelDescription.xml: what the loader needs of it (the model
// identifier that names the library, the GUID it must pass back, the step it can take, the real
// variables by name). Start-up only.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace flexloop::controller::fmu {

struct FmuVariable {
  std::string name, causality;  ///< causality: input, output, parameter, local, ...
  unsigned value_reference = 0;
  bool real = false;  ///< a <Real> variable
};

struct FmuDescription {
  std::string model_identifier, guid;
  bool variable_step = false;       ///< canHandleVariableCommunicationStepSize
  std::optional<double> step_size;  ///< DefaultExperiment stepSize
  std::vector<FmuVariable> variables;

  /// The real variable `name` of `causality`. @throws flexloop::InputError naming `fmu` when
  /// there is none (saying what there is instead).
  const FmuVariable& real(const std::string& name, const std::string& causality,
                          const std::string& fmu) const;
};

/// Reads `dir`/modelDescription.xml. @throws flexloop::InputError naming `fmu` when it is
/// missing or not XML, fmiVersion is not 2.0, there is no <CoSimulation> (Model Exchange only),
/// or the model identifier or GUID is missing.
FmuDescription read_fmu_description(const std::filesystem::path& dir, const std::string& fmu);

}  // namespace flexloop::controller::fmu
