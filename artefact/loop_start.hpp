// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Part of the loop artefact's schema: how a run starts (doc/design.md §5a). A run starts its
// loop in a draw from the loop's stationary distribution, so that the first sample is already
// the machine's, not a release from rest. `flexloop build` solves the discrete Lyapunov equation
// of the loop as it runs (floor filter, plant, the linear part of the hardware, controller,
// offline/scene/loop_start_builder.hpp) and stores the distribution of the loop's states given
// the floor filters' states; the online side draws the floor as before (its own seed) and the
// rest from this, with a seed of its own.
//
// The rows of a start, in this order (the runtime sets each where it lives):
//   x                      the plant's state (nx, the artefact's dense coordinates; the floor's
//                          own position and velocity among them are the floor's motion)
//   h                      the actuator force held since the last sample (nc)
//   s_{k-1} .. s_{k-d}     the sensor signal d samples back (d * ns; d = sensor + transport delay)
//   u_{k-1} .. u_{k-1-d}   the commands sent ((d + 1) * nc)
//   xc                     the controller's state (its own coordinates; none open loop)
//   l                      the actuator lag's force (nc, with a lag)
#include <Eigen/Core>
#include <string>

namespace flexloop::artefact {

struct StationaryStart {
  /// Empty: the start exists. Otherwise why the loop has no stationary state (runs start at rest).
  std::string unavailable = "not computed";
  std::string note;  ///< what the start leaves out (modes on the unit circle), or empty
  /// The relative change of the covariance to expect from rounding the loop's matrix (eps ||A||
  /// over the distance to the circle of its slowest decaying mode:
  /// plant/lti/stable_covariance.hpp); 0 where not computed (artefacts written before it was
  /// stored).
  double sensitivity = 0;
  int delay = 0;              ///< d of the rows above
  int controller_states = 0;  ///< rows of xc
  bool actuator_lag = false;  ///< rows l present
  /// n x (order * nw): the conditional mean of the rows given the floor filters' states, channel
  /// c's filter state in columns c * order .. (c + 1) * order - 1 (none for a white floor).
  Eigen::MatrixXd floor_gain;
  Eigen::MatrixXd covariance;  ///< n x n: the rows' covariance given the floor filters' states
  bool exists() const { return unavailable.empty(); }
};

/// Controller off (the plant alone, no command) and on (the artefact's controller closing the
/// loop).
struct LoopStart {
  StationaryStart open_loop, closed_loop;
};

}  // namespace flexloop::artefact
