// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant inside the exported plant FMU (issue 33): the artefact's discrete plant with its
// simulated hardware and floor (online/sim/loop_hardware.hpp, the same composition and seeds as
// `flexloop sim`), behind one virtual call per FMI step, since the FMU learns the hardware's
// effects only when it reads its artefact.
#include <memory>

#include "artefact/loop_artefact.hpp"

namespace flexloop::plant_fmu {

class PlantFmuModel {
 public:
  /// The artefact's plant and hardware, started in the open loop's stationary state (as `flexloop
  /// sim`'s controller-off run) or at rest. @throws flexloop::common::InputError naming the
  /// artefact, std::invalid_argument for counts the hardware does not take.
  static std::unique_ptr<PlantFmuModel> from_artefact(const artefact::LoopArtefact& a,
                                                      bool at_rest);
  virtual ~PlantFmuModel() = default;

  /// The sample at the current instant: the sensors (ns) then the performance sensors (nz).
  virtual void sample(double* readings) noexcept = 0;
  /// The command (nc) held until the next instant; the plant advances one period.
  virtual void apply(const double* command) noexcept = 0;
};

}  // namespace flexloop::plant_fmu
