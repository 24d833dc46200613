// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// From a loop artefact's discrete plant (artefact/loop_artefact.hpp) to the runtime plant that
// steps it: the one place `flexloop sim`, the plant process and the tradeoff study build it. A
// loop whose counts and form match a compiled loop (compiled_loops.hpp: with_compiled_loop on
// loop_counts) steps on that loop's fixed-size kernels (make_compiled_plant); every other loop on
// the general path, sized at start-up, in the form the artefact holds (with_general_plant). The
// plant holds the actuator commands itself (the last actuators() inputs, state_output.hpp).
#include <Eigen/Core>

#include "artefact/loop_artefact.hpp"
#include "plant/runtime/compiled_loops.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/general_plant.hpp"
#include "plant/runtime/modal_plant.hpp"

namespace flexloop::plant::runtime {

/// The artefact's counts and plant form, as the dispatch to a compiled loop compares them.
inline LoopCounts loop_counts(const artefact::LoopArtefact& a) {
  return {.states = a.plant.A.rows(),
          .disturbances = a.disturbances(),
          .actuators = a.actuators(),
          .performance = a.performance(),
          .sensors = a.sensors(),
          .form = a.plant.form};
}

/// The artefact's plant on the fixed-size kernels of a compiled loop, in double: a DensePlant or
/// a ModalPlant by Loop::kForm (the dispatch chose Loop for the artefact's counts and form).
/// @throws std::invalid_argument as DensePlant::from_matrices and ModalPlant::from_modal_form:
/// matrices of other sizes than Loop's, non-finite entries, a modal form that is not real
/// block-diagonal.
template <class Loop>
auto make_compiled_plant(const artefact::LoopArtefact& a) {
  const auto& d = a.plant;
  if constexpr (Loop::kForm == PlantForm::kModal)
    return ModalPlant<double, Loop::NX, Loop::NU, Loop::NY, Loop::NH>::from_modal_form(d.modal);
  else
    return DensePlant<double, Loop::NX, Loop::NU, Loop::NY, Loop::NH>::from_matrices(d.A, d.B, d.C,
                                                                                     d.D);
}

/// f(plant) for the artefact's plant on the general path, sized at start-up: a
/// GeneralModalPlant<Scalar> for the modal form, a GeneralDensePlant<Scalar> for the dense one.
/// Returns what f returns (the same type for both).
/// @throws std::invalid_argument as GeneralDensePlant::from_matrices and
/// GeneralModalPlant::from_modal_form: inconsistent sizes, non-finite entries, a modal form that
/// is not real block-diagonal, a decaying pole that Scalar cannot keep inside the unit circle.
template <typename Scalar, class F>
decltype(auto) with_general_plant(const artefact::LoopArtefact& a, F&& f) {
  const auto& d = a.plant;
  if (d.form == PlantForm::kModal)
    return f(GeneralModalPlant<Scalar>::from_modal_form(d.modal, a.actuators()));
  return f(GeneralDensePlant<Scalar>::from_matrices(d.A, d.B, d.C, d.D, a.actuators()));
}

}  // namespace flexloop::plant::runtime
