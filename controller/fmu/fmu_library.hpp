#pragma once
// An FMU's shared library (binaries/linux64/<modelIdentifier>.so) loaded with dlopen and the
// FMI 2.0 Co-Simulation calls the loop makes resolved from it. Start-up only.
#include <filesystem>
#include <string>

#include "common/fmi2.h"

namespace flexloop::controller::fmu {

struct Fmi2Calls {
  fmi2InstantiateTYPE* instantiate = nullptr;
  fmi2FreeInstanceTYPE* free_instance = nullptr;
  fmi2SetupExperimentTYPE* setup_experiment = nullptr;
  fmi2EnterInitializationModeTYPE* enter_initialization_mode = nullptr;
  fmi2ExitInitializationModeTYPE* exit_initialization_mode = nullptr;
  fmi2TerminateTYPE* terminate = nullptr;
  fmi2ResetTYPE* reset = nullptr;
  fmi2SetRealTYPE* set_real = nullptr;
  fmi2GetRealTYPE* get_real = nullptr;
  fmi2DoStepTYPE* do_step = nullptr;
  // Optional (nullptr when the library does not export them): asked after an fmi2Discard.
  fmi2GetRealStatusTYPE* get_real_status = nullptr;
  fmi2GetBooleanStatusTYPE* get_boolean_status = nullptr;
};

class FmuLibrary {
 public:
  /// @throws flexloop::InputError naming `fmu` with dlerror's text when the library does not
  /// load (missing, wrong architecture) or lacks one of Fmi2Calls' functions.
  FmuLibrary(const std::filesystem::path& dir, const std::string& model_identifier,
             const std::string& fmu);
  ~FmuLibrary();
  FmuLibrary(const FmuLibrary&) = delete;
  FmuLibrary& operator=(const FmuLibrary&) = delete;

  const Fmi2Calls& calls() const { return calls_; }

 private:
  void* handle_ = nullptr;
  Fmi2Calls calls_;
};

}  // namespace flexloop::controller::fmu
