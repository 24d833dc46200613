// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Static equilibrium under the model's loads (gravity, nodal forces, actuator stresses): the
// dynamic coordinates q_d with R_d(q_d, q_r, 0, 0) = 0 at rest, the prescribed coordinates q_r
// held at their reference. Newton's method with the exact tangent (Kbar + Gbar)_dd of the
// linearisation, so a preload enters through Gbar as it should. Linearising about the result
// gives the preloaded (e.g. gravity-loaded) plant.
#include <Eigen/Dense>

#include "plant/model/linearisation.hpp"
#include "plant/model/model.hpp"

namespace flexloop::plant::model {

struct StaticEquilibrium {
  OperatingPoint op;  ///< at rest at the equilibrium
  int iterations = 0;
  double residual_norm = 0;  ///< |R_d| at the end, in the units of the generalised forces
};

/// @throws std::runtime_error when Newton does not converge (e.g. beyond buckling: the message
/// says so) or the tangent is singular.
StaticEquilibrium static_equilibrium(const Model& m, int max_iterations = 30);

}  // namespace flexloop::plant::model
