// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Labelled state space (A, B, C, D) from a linearisation, for named inputs and outputs
// (doc/design.md §3, seed slides 14-17).
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
//
// Massless dynamic directions (a beam with lumped translational masses and no nodal rotary
// inertia leaves its bending directions without mass) are condensed statically. With
// Mdd = M̄dd, Cdd = C̄dd + D̄dd, Kdd = K̄dd + N̄dd + Ḡdd and g the generalised force of the inputs
// and prescribed coordinates (the right-hand side of the dynamic rows, doc/design.md §3), Z spans
// the null space of Mdd (eigenvalues <= 1e-10 of the largest, as model::condense_massless) and T =
// Y - Z (Z^T Kdd Z)^-1 Z^T Kdd Y is the static shape of the massive directions Y. The rows Z^T of
// the equations, without their damping term,
//   Z^T Kdd q = Z^T g,
// give q = R p + H g with H = Z (Z^T Kdd Z)^-1 Z^T and R = T T_P^-1, where P is a set of n_a
// dynamic coordinates picked by a pivoted QR of T^T weighted by sqrt(diag Mdd) (massive,
// well-conditioned coordinates first; R_P = I). The state is (p, p'), labelled pos:/vel: of the
// coordinates P; the other dynamic coordinates follow statically ("condensed"). The rows R^T:
//   R^T Mdd R p'' + R^T Cdd (R p' + H g') + R^T Kdd (R p + H g) = R^T g.
// Outputs use q = R p + H g, q' = R p' + H g', q'' = R p'' + H g'' (a massless coordinate's
// position gets the static map in C and the feedthrough H g in D).
//
// What this assumes, and where it is exact:
// - Static part: exact. The DC gain equals that of Kdd q = g (the stiffness of p is the Schur
//   complement of Kdd on the massless block), and the undamped dynamics of p are exact (the
//   finite eigenvalues of (Kdd, Mdd)).
// - Damping: the massless rows' damping Z^T Cdd q' is neglected (the relaxation of the massless
//   coordinates, time constants of (Z^T Kdd Z)^-1 Z^T Cdd Z, is taken as instantaneous); the
//   damping of the massive rows acts on the static shape. Exact when Z^T Cdd = 0;
//   Condensation::damping_coupling = ||Z^T Cdd||_F / ||Cdd||_F says how far from that.
// - Rates of inputs: g' and g'' use the prescribed coordinates' own signals (r' from vel: or its
//   integrator state, r'' from acc:). The rates of force and stress inputs (and r''') have no
//   place in a state space: the velocity of a massless coordinate under a force on it is an
//   improper response. They are left out of q', q'' and the damping term;
//   Condensation::rate_terms_dropped names the inputs concerned (empty: nothing left out).
// - p is the massive part of q_P: q_P = p + (H g)_P, equal to q_P when no input acts on a
//   massless direction, and always for coordinates without a massless component (e.g. nodal
//   translations when only the nodal rotations are massless).
#include <string>
#include <vector>

#include "plant/lti/state_space.hpp"
#include "plant/model/linearisation.hpp"

namespace flexloop::plant::lti {

/// What build_state_space condensed (massless_count == 0: nothing; the states are then every
/// dynamic coordinate and the other fields are empty or zero).
struct Condensation {
  int massless_count = 0;                       ///< massless directions condensed (n_b)
  std::vector<std::string> state_coordinates;   ///< the dynamic coordinates P kept as states
  std::vector<std::string> condensed;           ///< the dynamic coordinates that follow statically
  double damping_coupling = 0.0;                ///< ||Z^T Cdd||_F / ||Cdd||_F (~1e-16: exact)
  std::vector<std::string> rate_terms_dropped;  ///< inputs whose rates the massless part lacks
};

/// Throws flexloop::InputError (place "input 'name'" / "output 'name'") for unknown or
/// unsupported names, and (place: the model file) for an indefinite dynamic mass matrix or a
/// massless mechanism (massless directions without stiffness; the message names the coordinates).
StateSpace build_state_space(const model::Model& m, const model::Linearisation& lin,
                             const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs,
                             Condensation* condensation = nullptr);

}  // namespace flexloop::plant::lti
