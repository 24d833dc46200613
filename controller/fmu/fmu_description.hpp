// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// An FMI 2.0 Co-Simulation FMU's modelDescription.xml, read to the standard: what the loader needs
// of it (the model identifier that names the library, the GUID it must pass back, the step it can
// take, what the FMU needs of its process, the variables by name). Start-up only.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace flexloop::controller::fmu {

struct FmuVariable {
  std::string name;
  std::string causality = "local";         ///< input, output, parameter, local, ...
  std::string variability = "continuous";  ///< constant, fixed, tunable, discrete, continuous
  std::string type;                        ///< Real, Integer, Boolean, String or Enumeration
  unsigned value_reference = 0;            ///< required by the standard: always given
  bool real() const { return type == "Real"; }
};

struct FmuDescription {
  std::string model_identifier, guid;
  bool variable_step = false;           ///< canHandleVariableCommunicationStepSize
  bool only_once_per_process = false;   ///< canBeInstantiatedOnlyOncePerProcess
  bool can_run_asynchronously = false;  ///< canRunAsynchronuously (the standard's spelling)
  std::optional<double> step_size;      ///< DefaultExperiment stepSize
  std::vector<FmuVariable> variables;

  /// The Real variable `name` in the role `causality`: "input" (a sensor's), "output" (an
  /// actuator's) or "parameter" (one the scene sets: variability fixed or tunable).
  /// @throws flexloop::InputError naming `fmu` and the variable when there is none (saying what
  /// there is instead) or it is not a Real of that causality and variability (saying what it is).
  const FmuVariable& real(const std::string& name, const std::string& causality,
                          const std::string& fmu) const;
};

/// [A-Za-z_][A-Za-z0-9_]*: what a modelIdentifier must be (FMI 2.0: it names the library and
/// prefixes the C functions), so that the library's name stays one name in binaries/linux64.
bool is_c_identifier(std::string_view s);

/// Reads `dir`/modelDescription.xml. @throws flexloop::InputError naming `fmu` when it is
/// missing or not XML, fmiVersion is not 2.0, there is no <CoSimulation> (Model Exchange only),
/// the model identifier is missing or not a C identifier, the GUID is missing, the FMU needs its
/// execution tool (needsExecutionTool), or a variable has no name, no or a bad valueReference, no
/// type, or a name another variable has.
FmuDescription read_fmu_description(const std::filesystem::path& dir, const std::string& fmu);

}  // namespace flexloop::controller::fmu
