// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Disk margins of the sampled loop at the plant input (the actuator commands), as a control
// engineer reads them: how much gain and phase each loop -- and all loops at once -- can lose
// before the loop the runtime runs goes unstable (Seiler, Packard, Gahinet, "An introduction to
// disk margins", IEEE Control Systems Magazine, 2020; balanced disk, skew 0).
//
// A perturbation f_i in [(2 - a)/(2 + a), (2 + a)/(2 - a)] x e^{+-j phi}, phi = 2 atan(a/2), on
// the command of loop i (loop at a time: the other loops closed and unperturbed) leaves the loop
// stable for a < a_i = 1 / max_w |S_ii(e^{jwT}) - 1/2|, with S = I + H the input sensitivity and
// H the transfer from a perturbation added to the command to the command
// (sampled_loop_stability.hpp, SampledLoopModel). Every channel perturbed at once, independently:
// a_all = 1 / max_w sigma_max(S - I/2) is a guaranteed lower bound (unstructured; a mu analysis
// of the diagonal perturbation can only give more). The loop must be stable for any of this to
// mean something: the margins are not formed for an unstable loop.
//
// The peak is searched on a log grid from 1e-6 of the Nyquist frequency up to Nyquist, with the
// frequency of each of the loop's complex poles added (a lightly damped pole's peak can be
// narrower than any grid's spacing: 0.1 % damping is 0.2 % wide), refined
// around the largest point by golden-section search in log frequency. The search reads the loop
// on its complex Schur form (half the cost a point); each margin's value is then the Hessenberg
// one at the frequency the search settles on, as analyse has always read it.
#include <Eigen/Dense>
#include <vector>

#include "controller/design/sampled_loop_stability.hpp"

namespace flexloop::controller::design {

struct DiskMargin {
  double alpha = 0;         ///< disk size a (0: none)
  double gain_low = 1;      ///< guaranteed gain factors: [(2 - a)/(2 + a), (2 + a)/(2 - a)]
  double gain_high = 1;     ///< +infinity for a >= 2
  double phase_deg = 0;     ///< guaranteed phase, +-: 2 atan(a/2)
  double frequency_hz = 0;  ///< where |S - 1/2| peaks (the critical frequency)
};

/// The margin a disk of size alpha guarantees (the frequency is left 0).
DiskMargin disk_margin_of(double alpha);

struct InputDiskMargins {
  std::vector<DiskMargin> loops;  ///< one per actuator command, loop at a time
  DiskMargin all_loops;           ///< every command at once (the unstructured lower bound)
};

/// Options of the peak search.
struct DiskMarginOptions {
  int points = 500;  ///< log-grid points up to Nyquist, >= 16 (the poles' frequencies added)
};

/// @throws std::invalid_argument for a loop model whose sizes do not close, or points < 16;
/// std::domain_error when a pole of the loop sits on the unit circle at a grid frequency.
InputDiskMargins input_disk_margins(const SampledLoopModel& loop,
                                    const DiskMarginOptions& options = {});

}  // namespace flexloop::controller::design
