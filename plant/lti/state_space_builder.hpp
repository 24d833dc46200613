#pragma once
// Labelled state space (A, B, C, D) from a linearisation, for named inputs and outputs
// (DESIGN.md §3, seed slides 14-17).
//
// State: z = (dq_d, dq_d'), plus integrator states (dq_r, dq_r') of a prescribed coordinate
// whose acceleration (or velocity) alone is an input while the dynamics or the chosen outputs
// depend on its position or velocity (seed slide 24, note 2).
//
// Input names:   force:<coordinate>     nodal force component df, N (or N m)
//                stress:<deformation>   actuator stress dsigma_a
//                pos:<prescribed>, vel:<prescribed>, acc:<prescribed>
//                                       a rheonomic coordinate as position, velocity or
//                                       acceleration (any combination per coordinate)
// Output names:  pos:<coordinate or deformation>, vel:<coordinate>, acc:<coordinate>
//                stress:<deformation>   stress resultant sigma of a flexible/released deformation
#include <string>
#include <vector>

#include "plant/lti/state_space.hpp"
#include "plant/model/linearisation.hpp"

namespace flexloop::plant::lti {

/// Throws flexloop::InputError (place "input 'name'" / "output 'name'") for unknown or
/// unsupported names, and for a singular dynamic mass matrix (naming the coordinates).
StateSpace build_state_space(const model::Model& m, const model::Linearisation& lin,
                             const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs);

}  // namespace flexloop::plant::lti
