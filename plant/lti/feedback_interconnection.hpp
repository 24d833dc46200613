// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Closing a loop around a generalised plant (doc/design.md §4, seed slide 33).
//
// The plant's inputs are [w; u] (first n_w disturbances w, then the actuator inputs u) and its
// outputs [z; y] (first n_z performance outputs z, then the measured outputs y):
//   x' = A x + B1 w + B2 u,   z = C1 x + D11 w + D12 u,   y = C2 x + D21 w + D22 u.
// The controller maps y to u (positive-feedback convention of the seed, u = C y):
//   xc' = Ac xc + Bc y,       u = Cc xc + Dc y.
//
// Continuous closed loop (states [x; xc], input w, output z): with E = (I - Dc D22)^-1,
//   u = E (Dc C2 x + Cc xc + Dc D21 w),  y = C2 x + D21 w + D22 u,
// so that its transfer function is T = G11 + G12 C (I - G22 C)^-1 G21 (`lft_closed_loop`).
//
// Sampled closed loop, the exact model of the simulation and real-time loops. At instant k the
// sensors see the command still held from k - 1: y_k = C2 x_k + D21 w_k + D22 u_{k-1}. The
// controller knows that command, removes its feedthrough, f_k = y_k - D22 u_{k-1}, and solves
// the loop algebraically as the continuous law does (a plain u_k = Cc xc + Dc y_k would feed its
// own command back with a one-sample delay: unstable once |Dc D22| > 1, e.g. a force-feedback
// proportional gain above 1). The answer is held until k + 1:
//   u_k = E (Cc xc_k + Dc f_k),   xc_{k+1} = Ac xc_k + Bc (f_k + D22 u_k),
//   x_{k+1} = A x_k + B1 w_k + B2 u_k,   z_k = C1 x_k + D11 w_k + D12 u_{k-1}.
// The held command is a state (for z): states [x; xc; u_held].
#include <Eigen/Dense>

#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

struct LoopPartition {
  Eigen::Index disturbances;  ///< n_w: the first plant inputs; the rest are the actuator inputs
  Eigen::Index performance;   ///< n_z: the first plant outputs; the rest are the measured outputs
};

/// @throws std::invalid_argument when sizes disagree (controller inputs = measured outputs,
/// controller outputs = actuator inputs) or when I - Dc D22 is singular (ill-posed loop).
StateSpace close_loop(const StateSpace& plant, const StateSpace& controller, LoopPartition part);

/// Plant and controller discretised with the same sample time. Same exceptions.
DiscreteStateSpace close_loop_sampled(const DiscreteStateSpace& plant,
                                      const DiscreteStateSpace& controller, LoopPartition part);

/// T = G11 + G12 C (I - G22 C)^-1 G21 for one frequency point (reference formula).
Eigen::MatrixXcd lft_closed_loop(const Eigen::MatrixXcd& G, const Eigen::MatrixXcd& C,
                                 LoopPartition part);

}  // namespace flexloop::plant::lti
