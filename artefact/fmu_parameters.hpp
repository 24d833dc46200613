// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Part of the loop artefact's schema: a controller FMU's start-up parameters (issue 33): the FMI
// 2.0 Co-Simulation FMU the loop runs (controller/fmu), the SHA-256 of the file that was built
// into the artefact, the parameters the scene sets, and the FMU's real variables the loop
// connects, in the channel map's order, and the cap on the unpacked archive when the scene sets
// one.
#include <optional>
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
  /// The cap on the archive's unpacked size [MB = 2^20 bytes] (scene: [controller]
  /// fmu_max_unpacked_mb; JSON: max_unpacked_mb, optional); none: the loader's default
  /// (controller/fmu/fmu_archive.hpp).
  std::optional<long> max_unpacked_mb;
};

/// What fmu_max_unpacked_mb may be: 1 MB .. 1 TiB.
inline constexpr long kMaxFmuUnpackedMb = 1L << 20;

}  // namespace flexloop::artefact
