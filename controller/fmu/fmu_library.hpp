// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// An FMU's shared library (binaries/linux64/<modelIdentifier>.so) loaded with dlopen and the
// FMI 2.0 Co-Simulation calls the loop makes resolved from it. Start-up only.
//
// Before dlopen (which runs the library's constructors): the model identifier is a C identifier
// and the library's canonical path (links resolved) lies inside the unpacked FMU's folder; an FMU
// that can be instantiated only once per process is not loaded while another copy of it (the same
// GUID) is. After dlopen, before any instance: fmi2GetTypesPlatform returns "default" and
// fmi2GetVersion "2.0" (the types and calls flexloop passes are the standard's).
#include <filesystem>
#include <string>

#include "common/fmi2.h"
#include "controller/fmu/fmu_description.hpp"

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
  /// The library of the FMU unpacked in `dir` as `description` describes it (one instance per
  /// library: a once-per-process FMU holds its claim while this lives). @throws
  /// flexloop::InputError naming `fmu`: a model identifier that is not a C identifier, a library
  /// outside `dir`, a second copy of a once-per-process FMU, a library that does not load
  /// (dlerror's text: missing, wrong architecture), another types platform or FMI version, or a
  /// missing one of Fmi2Calls' functions.
  FmuLibrary(const std::filesystem::path& dir, const FmuDescription& description,
             const std::string& fmu);
  /// The same, reading `dir`'s modelDescription.xml for the rest, which must name
  /// `model_identifier`.
  FmuLibrary(const std::filesystem::path& dir, const std::string& model_identifier,
             const std::string& fmu);
  ~FmuLibrary();
  FmuLibrary(const FmuLibrary&) = delete;
  FmuLibrary& operator=(const FmuLibrary&) = delete;

  const Fmi2Calls& calls() const { return calls_; }

 private:
  /// The GUID of a once-per-process FMU, released when the library goes; empty for any other.
  struct ProcessClaim {
    std::string guid;
    ProcessClaim(const FmuDescription& d, const std::string& fmu);
    ~ProcessClaim();
    ProcessClaim(const ProcessClaim&) = delete;
    ProcessClaim& operator=(const ProcessClaim&) = delete;
  };
  ProcessClaim claim_;
  void* handle_ = nullptr;
  Fmi2Calls calls_;
};

}  // namespace flexloop::controller::fmu
