// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The figures of a scene's loop, one function each, as `flexloop analyse` prints them and a
// campaign sample (offline/campaign/sample_figures.hpp) records them: the same code for both, so
// that a figure of the nominal machine is the same number in either.
#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "controller/design/disk_margins.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::pipeline {

/// The verdict analyse states: the continuous loop stable (where there is one; a discrete
/// controller has none) and the sampled loop as it runs stable. nullopt sampled: not formed.
bool closed_loop_stable(const scene::ScenePlant& p,
                        const std::optional<controller::design::SampledLoopStability>& sampled);

/// Disk margins of the sampled loop at the actuator commands (controller/design/disk_margins.hpp),
/// loop at a time and all at once. @throws flexloop::InputError when the discretisation is
/// refused; std::domain_error when a loop pole sits on the unit circle at a grid frequency.
controller::design::InputDiskMargins loop_disk_margins(const scene::ScenePlant& p);

/// The passive path floor -> performance G11 of the plant G.
plant::lti::StateSpace floor_to_performance(const scene::ScenePlant& p);

/// The closed loop floor -> performance T at `frequencies_hz`: the continuous closed loop where
/// the loop has a continuous form (the PI, a continuous state space), else the sampled closed
/// loop (z = e^{j w T}) of `sampled` (scene::sample_scene(p)), which only that case needs. The
/// scene must have a controller. @throws std::invalid_argument when `sampled` is needed and null.
std::vector<Eigen::MatrixXcd> closed_loop_response(const scene::ScenePlant& p,
                                                   const scene::SampledScene* sampled,
                                                   const std::vector<double>& frequencies_hz);

/// The loop as it runs against its continuous design, floor -> performance, at the frequencies of
/// `frequencies_hz` below Nyquist: the largest singular value of the sampled closed loop
/// (`sampled`: the scene's plant and controller sampled at its rate and closed as the runtime
/// closes them, the hardware's effects aside) and of the continuous one, and where the sampled
/// one exceeds both the design and the passive machine most, judged from a tenth of the lowest
/// passive natural frequency to half Nyquist (a sampled loop that stays under the passive
/// response is not judged by how much deeper its design reaches; the held command's steps lift
/// the response near Nyquist, and a held floor's sample-long lag feeds a pure integrator at the
/// lowest frequencies: both are how a sampled loop is). A sampled force loop cannot act as
/// designed on modes near or above Nyquist: aliased, they reach the whole band through the
/// controller.
struct SampledAgainstDesign {
  std::vector<double> f;            ///< the frequencies below Nyquist
  Eigen::VectorXd sampled, design;  ///< largest singular values at f
  double judged_from_hz = 0, judged_to_hz = 0;
  double excess_db = 0, excess_hz = 0;  ///< largest 20 log10(sampled / max(design, open)), where
  int modes_above_nyquist = 0;          ///< of the scene's plant (oscillatory pole pairs)
};
/// The scene must have a continuous loop (scene::has_continuous_loop).
SampledAgainstDesign sampled_against_design(const scene::ScenePlant& p,
                                            const scene::SampledScene& sampled,
                                            const std::vector<double>& frequencies_hz);

/// The largest singular value of each response.
Eigen::VectorXd largest_singular_values(const std::vector<Eigen::MatrixXcd>& responses);

/// The stationary RMS of each performance output of the loop as it runs, made linear (the ADC's
/// rounding as uniform noise LSB²/12): exact, by the discrete Lyapunov equation of floor filter,
/// plant, hardware, sensor noise and controller (offline/scene/loop_start_builder.hpp).
/// closed: with the scene's controller, else open loop.
/// @throws std::invalid_argument when the loop has no stationary state (saying why).
Eigen::VectorXd stationary_rms(const scene::ScenePlant& p, const scene::SampledScene& sampled,
                               bool closed);

}  // namespace flexloop::pipeline
