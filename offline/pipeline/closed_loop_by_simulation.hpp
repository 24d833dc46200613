// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The sampled closed loop w -> z measured by simulation, for a loop whose controller cannot be
// seen into (a controller FMU has no matrices): what `flexloop analyse` shows for it instead of
// the matrices' closed loop (issue 33). One impulse per disturbance channel, each from rest (the
// plant at x = 0, no command held, the controller reset), stepped with the sampling convention of
// plant::lti::close_loop_sampled and of `flexloop sim`:
//
//   y_k = C2 x_k + D21 w_k + D22 u_{k-1},   u_k = controller.step(y_k),
//   z_k = C1 x_k + D11 w_k + D12 u_{k-1},   x_{k+1} = A x_k + B1 w_k + B2 u_k,
//   w_k = a e_j for k = 0, else 0.
//
// z / a are the closed loop's Markov parameters; their transform (plant::lti::
// ImpulseResponseTransform) is its frequency response T(e^{j w dt}). The loop is the linear one:
// the artefact's discrete plant and controller, without the hardware effects (no noise,
// quantisation or saturation of the plant's side; the controller's own limits stay, and a small
// impulse stays inside them). For a controller that is linear the result is the closed loop's
// response up to the truncation bound; for one that is not, the response to this impulse.
//
// Each channel runs until its responses have settled: over a block of samples and since the
// block before, z and u moved less than decay_tolerance times their peaks, or max_samples. They
// settle to zero, or to a constant where the loop leaves an integrator undamped (a pole at
// z = 1: the PI force feedback without leak holds a self-equilibrated force, or drives a free
// mass); the constant is carried to infinity analytically (plant::lti::ImpulseResponseTransform::
// add_constant_tail), exact for a simple pole at z = 1 and infinite at f = 0. The decay per
// sample is estimated from how the spread shrank from 1e-6 of the peak to the end (the slowest
// pole the run saw inside the unit circle), and the truncation bound from it: spread / (1 - decay),
// relative to the peak. A response that grows past 1e12 times its first peak, or is not finite,
// is a diverging loop: the run stops and says so. An undamped oscillation (a pole on the unit
// circle at f > 0) never settles: the run ends at max_samples and says so.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"

namespace flexloop::pipeline {

struct ImpulseSettings {
  double amplitude = 1.0;          ///< the impulse a, in the disturbance channel's unit
  double decay_tolerance = 1e-13;  ///< a block that moves less than this share of the peak
  long max_samples = 1L << 18;     ///< per channel
  long block_samples = 2048;
};

struct ClosedLoopBySimulation {
  std::vector<Eigen::MatrixXcd> response;  ///< per frequency asked: nz x nw, T(e^{j 2 pi f dt})
  long samples = 0;                        ///< the longest channel's run
  bool decayed = false;                    ///< every channel settled (to zero or a constant)
  bool diverged = false;                   ///< a channel grew without bound: the loop is unstable
  double tail = 0;                 ///< largest over channels: the last block's spread / peak of z
  double constant_tail = 0;        ///< largest |z| it settled to / peak: 0 unless a pole at z = 1
  double decay_per_sample = 0;     ///< largest over channels; 0 when too short to tell
  double truncation_bound = 0;     ///< largest over channels: tail / (1 - decay), relative
  std::string controller_failure;  ///< a controller FMU's failed call; empty for none
};

/// The closed loop of `a` (its plant and controller, any kind with_controller builds) by
/// simulation at `frequencies_hz`. progress(channel, samples) after each block.
/// @throws flexloop::InputError as with_controller (no controller, a refused FMU).
ClosedLoopBySimulation closed_loop_by_simulation(
    const artefact::LoopArtefact& a, const std::vector<double>& frequencies_hz,
    const ImpulseSettings& settings = {},
    const std::function<void(Eigen::Index channel, long samples)>& progress = {});

}  // namespace flexloop::pipeline
