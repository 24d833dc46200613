// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Offline: the stationary starts of a loop artefact (artefact/loop_start.hpp, doc/design.md §5a).
//
// The loop as it runs, made linear (saturation and the ADC's rounding left out; the ADC's
// rounding counted as white noise of LSB²/12, as the sensor noise is), is one discrete system
// driven by unit white noise: the floor filters (one per disturbance channel), the plant, the
// held force, the sensor and transport delay, the controller and the actuator lag
// (controller/design/sampled_loop_stability.hpp builds its one-step matrix). The white noise of
// sample k is part of the state, so that the sensor noise and the floor's feedthrough enter the
// loop where the runtime puts them. Its stationary covariance P = Φ P Φᵀ + Γ Γᵀ
// (numeric/stationary_covariance.hpp) exists when every mode the noise drives is inside the unit
// circle; a mode on the circle that no noise reaches (the pure integrator of a force feedback
// whose plant has a zero at s = 0) is left where it starts, at zero.
//
// A plant with the floor's own position and velocity among its states (gravity preload) has
// them as a 2x2 Jordan block at z = 1 per channel: the floor drifts, the structure relative to it
// does not. Those states are the floor's motion (the filter's rows `motion`), so in the
// computation they are replaced by it, and the structure stands on a floor that is stationary.
// The runtime still steps them as states, started at the floor's motion.
//
// The start is stored given the floor filters' state, which the floor generator draws itself
// (same seed, same floor as a start from rest).
#include "artefact/loop_artefact.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/stable_covariance.hpp"

namespace flexloop::scene {

/// The open-loop and closed-loop starts of `a` (its plant, floor, effects and controller set). A
/// loop without a stationary state gets `unavailable` saying why. Cost: a few products of the
/// loop's size a round for about log2(1/(1 - |z|max)) rounds (the 206-state arm: about a second).
artefact::LoopStart stationary_loop_start(const artefact::LoopArtefact& a);

/// The stationary covariance of the loop's states (rows as artefact/loop_start.hpp) together with
/// the performance outputs' mean squares, for the reports and tests that compare a run with the
/// exact value. Empty when the loop has no stationary state.
struct StationaryMoments {
  Eigen::VectorXd performance_mean_square;  ///< E[z_i²] of the true performance outputs
  Eigen::VectorXd command_mean_square;      ///< E[u_i²] (zero open loop)
};
/// closed: with the artefact's controller (it must have one) or open loop.
/// @throws std::invalid_argument when the loop has no stationary state (saying why).
StationaryMoments stationary_moments(const artefact::LoopArtefact& a, bool closed);

/// The loop as one linear system driven by unit white noise, x+ = A x + noise n (states as in
/// stationary_moments, before the start is conditioned on the floor filters), and the stationary
/// covariance of its part inside the unit circle: for tests and diagnostics that check the
/// start against its Lyapunov equation. @throws std::invalid_argument as stationary_moments.
struct StationaryLoop {
  Eigen::MatrixXd A, noise;
  plant::lti::StableCovariance stable;
};
StationaryLoop stationary_loop(const artefact::LoopArtefact& a, bool closed);

/// The same moments on the continuous floor (doc/design.md §5a, issue 35 item 2): the scene's
/// continuous plant and its VC floor filter driven by continuous white noise, sampled exactly
/// together (Van Loan), the actuators held and the controller discrete as in the runtime loop. The
/// runtime holds the floor's sample-mean acceleration instead: the two differ by what the hold
/// does between samples. `p` is the scene `a` was built from (unreduced).
/// @throws std::invalid_argument for a white floor, a reduced plant, or no stationary state.
StationaryMoments continuous_floor_moments(const ScenePlant& p, const artefact::LoopArtefact& a,
                                           bool closed);

}  // namespace flexloop::scene
