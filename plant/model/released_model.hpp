// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Equations of reaction by virtual work (seed slides 8, 12-13): the force that holds a fixed
// nodal coordinate, or the stress in a rigid deformation, is the generalised force of that
// coordinate's equation of motion once it is released into a prescribed generalised coordinate
// held at its present value. Linearising the released model gives the linearised reaction
// exactly, with the same machinery (and tests) as the equations of motion.
#include <string>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

/// A copy of `m` in which `label` (a fixed coordinate, or a rigid deformation) is a prescribed
/// generalised coordinate appended after the existing ones. Throws flexloop::InputError when the
/// label is neither.
Model release_to_prescribed(const Model& m, const std::string& label);

}  // namespace flexloop::plant::model
