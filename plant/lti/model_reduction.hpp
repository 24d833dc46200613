// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Offline model reduction of a continuous LTI system  dz/dt = A z + B u,  y = C z + D u
// (doc/design.md §8): fewer states with the same inputs and outputs (labels kept; the states of a
// reduced model are modal or balanced coordinates, labelled "mode:<k>" / "balanced:<k>").
//
// Modal truncation. A = T Λ T^-1 in real block-diagonal form (a 1x1 block per real eigenvalue, a
// 2x2 block [[a, b], [-b, a]] per pair a ± jb; T from the eigenvectors of the exactly balanced
// A, refused when nearly defective; the poles at the origin, Jordan blocks or not, as one block
// spanning the null space of A^m, m their count). Each mode's contribution is its own transfer
// C_m (sI - A_m)^-1 B_m at its resonance (s = j|b|, or 0 for a real pole), each input-output pair
// relative to the full system's peak |G_ij| on a frequency grid spanning the poles, the largest
// pair counting: a weighting that no unit choice (N against m/s^2) can dominate. Modes with a
// pole at the origin (rigid bodies, integrators: infinite contribution) and unstable ones are
// always kept. The kept modes: the `order` states of largest contribution (a pair is never split,
// so the result may have one state fewer), or every mode below `below_hz`.
// Static correction (dc_correction): D_r = D - Σ_discarded C_m A_m^-1 B_m, so that the reduced
// model's DC gain equals the full one (the discarded modes respond quasi-statically), at the
// price of a feedthrough at high frequency.
//
// Balanced truncation: SLICOT AB09MD (square-root Balance & Truncate, with scaling). The part of
// the system with poles at Re s >= alpha (half the real part of the least damped stable pole
// away from the origin: rigid-body, integrator and unstable modes) is kept whole; the stable part
// is balanced and truncated to order - (kept part's order). Hankel singular values σ_1 >= σ_2 >=
// ... of the stable part, and the a-priori bound
//   ||G - G_r||_∞ <= 2 Σ_{discarded} σ_i.
// D is kept.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

struct ReducedModel {
  StateSpace sys;
  std::string method;  ///< "modal", "modal-dc", "balanced"
  /// Balanced: the stable part's Hankel singular values, descending; modal: empty.
  Eigen::VectorXd hankel_singular_values;
  /// Balanced: 2 Σ of the discarded Hankel singular values (an upper bound of ||G - G_r||_∞);
  /// modal: NaN (no a-priori bound).
  double error_bound = 0;
  int kept_unstable = 0;  ///< states kept whole (poles at the origin or unstable)
};

struct ModalTruncationOptions {
  int order = -1;       ///< >= 0: at most this many states (the most important modes)
  double below_hz = 0;  ///< > 0 (with order < 0): the modes whose |pole| is below this
  bool dc_correction = false;
  double max_condition = 1e8;  ///< refuse a nearly defective A (eigenvector condition above)
  /// > 0: judge contributions in the band [band_low_hz, band_hz] (the peaks, and each mode at its
  /// frequency held inside the band: a mode above it counts with its quasi-static tail at the
  /// band's top, however sharp its own resonance); 0: everywhere
  double band_low_hz = 0, band_hz = 0;
  /// Labels of states to express the block of the poles at the origin in (the floor's position
  /// and velocity): when they are as many as those poles and span their block, the reduced
  /// model keeps them, with their labels, as exact coordinates (states that only the inputs
  /// drive have no component in the stable modes); otherwise that block is in modal coordinates
  /// too ("mode:<k>", like every kept mode).
  std::vector<std::string> origin_states = {};
};

/// @throws std::invalid_argument for an invalid system, neither order nor below_hz given, or a
///         nearly defective A (cond of the eigenvector matrix above max_condition).
ReducedModel modal_truncation(const StateSpace& sys, const ModalTruncationOptions& o);

/// Balanced truncation to `order` states (at least the kept part's order).
/// @throws std::invalid_argument for an invalid system or order < 0; std::runtime_error when
///         SLICOT reports a failure (its INFO code and meaning in the message).
ReducedModel balanced_truncation(const StateSpace& sys, int order);

/// The modal contributions used by modal_truncation, one per mode, in the order of `frequencies`
/// (|pole| / 2π, ascending): what a user choosing `order` wants to see.
struct ModeContribution {
  double frequency_hz;  ///< |λ| / 2π
  double damping;       ///< -Re λ / |λ| (1 for a real stable pole); NaN at the origin (none)
  int states;           ///< 1 or 2; at the origin, the block of all its poles
  bool at_origin;       ///< the poles at s = 0 (integrators, rigid bodies), one block
  double contribution;  ///< relative peak, as above; +inf for a pole at the origin or unstable
};
std::vector<ModeContribution> modal_contributions(const StateSpace& sys,
                                                  const ModalTruncationOptions& o = {});

}  // namespace flexloop::plant::lti
