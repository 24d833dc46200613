// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The collocated struts of a PI force-feedback scene (controller/design/pi_force_feedback.hpp):
// which design rule applies, the pairing of each actuator with the force sensor of its own strut,
// and each strut's stiffness k_i and inverse mass 1/m_i for the per-strut design.
#include <vector>

#include "controller/design/pi_force_feedback.hpp"
#include "offline/scene/scene.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model.hpp"

namespace flexloop::scene {

/// True when the seed's coupled rule applies: one actuator per dynamic coordinate, actuator i
/// the stress of the i-th dynamic coordinate (the struts are the coordinates, in their order).
bool struts_are_the_coordinates(const Scene& scene, const plant::model::Model& m);

/// Checks that actuator i and sensor i are the stress "stress:<deformation>" of one strut (the
/// actuator's collocated force sensor). @throws flexloop::InputError at the scene file's [plant]
/// actuators or sensors entry that breaks the pairing.
void require_collocated_pairs(const Scene& scene, const plant::model::Model& m);

/// The struts in the scene's actuator order: k_i = S_ii of the deformation, 1/m_i = -(C A B)_ii
/// of the actuators -> elongations path (its s^-2 Markov parameter; no damping term enters it).
/// @throws flexloop::InputError at the scene's entry of a strut without stiffness or mass.
std::vector<controller::design::CollocatedStrut> collocated_struts(
    const Scene& scene, const plant::model::Model& m, const plant::model::Linearisation& lin);

}  // namespace flexloop::scene
