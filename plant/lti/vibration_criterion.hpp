// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Vibration-criterion (VC) floor curves and the shaping filter that makes a floor follow one
// (doc/design.md §6, issue 6). Offline: the online FloorGenerator (plant/runtime/effects) runs the
// discretised filter.
//
// The curves. One-third-octave band RMS velocity, the same in every band from 1 to 80 Hz:
//   VC-A 50, VC-B 25, VC-C 12.5, VC-D 6.25, VC-E 3.12 µm/s
// as in IEST-RP-CC012.2 (2007) and Amick, Gendreau, Busch and Gordon, "Evolving criteria for
// research facilities: vibration", Proc. SPIE 5933 (2005), which extended every curve flat in
// velocity down to 1 Hz. The original curves (Ungar and Gordon 1983; Gordon, Proc. SPIE 1619
// (1991)) held VC-A and VC-B at constant acceleration (260 and 130 µg) from 4 to 8 Hz; that
// edition is NOT implemented: here every curve is flat in velocity over all of 1-80 Hz.
//
// Bands: IEC 61260-1 base ten, exact centres fc = 10^(n/10) Hz for n = 0..19 (nominal 1, 1.25,
// 1.6, ..., 63, 80 Hz), edges fc 10^(±1/20). A one-sided velocity PSD S_v(f) = K / f puts
//   V² = ∫ S_v df = K ln(10^(1/10))      in every band, so K = V² / (0.1 ln 10),
// i.e. acceleration PSD S_a(f) = (2πf)² S_v(f) = 4π² K f (rising as f: a half-order
// differentiator of white noise).
//
// The shaping filter, input w continuous white noise of unit intensity (E[w(t) w(t+τ)] = δ(τ),
// one-sided output PSD 2|H(j2πf)|²), output floor acceleration [m/s²]:
//   H(s) = g · s²/(s² + √2 ω_hp s + ω_hp²) · Π_{k=1..M} (s + z_k)/(s + p_k) · ω_lp²/(s² + √2 ω_lp s
//   + ω_lp²)
// The product is Oustaloup's recursive approximation of s^(1/2) between ω_b and ω_h:
//   z_k = ω_b u^((k - 3/4)/M),  p_k = ω_b u^((k - 1/4)/M),  u = ω_h/ω_b,
// i.e. zeros and poles interleaved at equal log spacing, whose mean slope is 10 dB/decade. The
// two Butterworth factors roll the floor off outside the criterion's range: acceleration falls as
// f² below ω_hp (so velocity and displacement stay bounded) and as 1/f² above ω_lp. The gain g
// centres the band errors (their largest and smallest dB error are equal and opposite).
// Strictly proper (D = 0), all poles real except the two Butterworth pairs; order M + 4.
//
// The default options were picked by a scan over (ω_b, ω_h, M, ω_hp, ω_lp) for the lowest order
// whose worst band error stays below 0.1 dB continuous and at 2 kHz, 0.25 dB at 1 kHz
// (tests/effects/test_floor.cpp).
// Accuracy of the default design (order 9), from filter_band_velocity_rms, checked by
// tests/effects: the continuous filter is within ±0.08 dB of the curve in all 20 bands 1-80 Hz;
// its discretisation (discretise_floor_filter: zoh, sample-mean output) within ±0.08 dB at 2, 5
// and 10 kHz, and -0.20 dB in the 80 Hz band at 1 kHz (the hold's sinc and the sample mean's,
// -0.09 dB each there). Below 1 kHz the 80 Hz band nears Nyquist. Outside the range the level
// falls: -1.8 dB at 0.4 Hz, -20 dB at 0.1 Hz, -0.8 dB at 160 Hz, -9 dB at 400 Hz (band levels at
// those centres).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space.hpp"

namespace flexloop::plant::lti {

enum class VibrationCriterion { kVcA, kVcB, kVcC, kVcD, kVcE };

/// "VC-A" ... "VC-E"; throws std::invalid_argument listing them.
VibrationCriterion parse_vibration_criterion(const std::string& name);
std::string to_string(VibrationCriterion criterion);

/// The criterion's one-third-octave band RMS velocity [m/s] (the same in every band 1-80 Hz).
double criterion_band_velocity_rms(VibrationCriterion criterion);

struct ThirdOctaveBand {
  double nominal_hz;  ///< the band's name, e.g. 31.5
  double centre_hz;   ///< exact base-ten centre 10^(n/10)
  double lower_hz, upper_hz;
};

/// The 20 bands of the criteria, nominal centres 1 ... 80 Hz.
std::vector<ThirdOctaveBand> criterion_bands();

struct FloorFilterOptions {
  double approximation_low_hz = 0.1;   ///< ω_b / 2π, lower end of the s^(1/2) approximation
  double approximation_high_hz = 600;  ///< ω_h / 2π
  int pole_zero_pairs = 5;             ///< M
  double high_pass_hz = 0.35;          ///< ω_hp / 2π
  double low_pass_hz = 250;            ///< ω_lp / 2π
};

/// Order of the default design: M + 4.
inline constexpr int kFloorFilterOrder = 9;

/// The continuous shaping filter for a band RMS velocity V [m/s] (one input "white noise", one
/// output "floor acceleration", labelled).
/// @throws std::invalid_argument unless V > 0 and the options are finite, positive and ordered
///         (approximation_low_hz < approximation_high_hz, pole_zero_pairs >= 1).
StateSpace design_floor_filter(double band_velocity_rms, const FloorFilterOptions& options = {});

/// Zero-order hold of the filter at sample time dt with its input scaled by 1/sqrt(dt), so that a
/// unit-variance white sequence n_k drives it: u_k = n_k / sqrt(dt) held over a sample has the
/// low-frequency PSD of the unit-intensity continuous noise. The matrices the online
/// FloorGenerator takes.
///
/// Its output is the floor acceleration averaged over the sample, (v_{k+1} - v_k)/dt with v the
/// floor velocity at the sample instants, not the acceleration at the instant: a plant that
/// integrates the held acceleration (the floor's position and velocity are states of a
/// gravity-preloaded plant) then follows the floor's own velocity exactly, where the point
/// samples would leave a bounded velocity error and a displacement that drifts. In band the two
/// differ by the sample's sinc: -0.09 dB at 80 Hz at 1 kHz, -0.001 dB at 10 kHz.
/// @throws std::invalid_argument as discretise() does, or when the filter is not a floor filter
///         whose displacement is stationary (see floor_motion_outputs).
DiscreteStateSpace discretise_floor_filter(const StateSpace& filter, double dt);

/// Velocity and displacement of the floor as functions of the filter's state (rows: velocity
/// [m/s], displacement [m]; the state is the same in the continuous and the discretised filter):
/// H(s) = s² P(s) with P the displacement's transfer function, so with A invertible and
/// C A⁻¹ B = C A⁻² B = 0 (H has a double zero at s = 0), v = C A⁻¹ x and p = C A⁻² x. A gravity-
/// preloaded plant starts its floor states there, so that the floor it integrates is the same
/// stationary floor the generator draws. @throws std::invalid_argument when A is singular or H
/// lacks the double zero (a floor whose displacement would not be stationary).
Eigen::MatrixXd floor_motion_outputs(const StateSpace& filter);

/// Band RMS velocity the filter's output has in each band [m/s]: ∫ S_a(f) / (2πf)² df over the
/// band (Simpson's rule in log f, 64 intervals), S_a = 2|H(j2πf)|² for the continuous filter
/// (unit-intensity input), S_a = 2 dt |H(e^{j2πf dt})|² for the discrete one (unit-variance
/// input). @throws std::invalid_argument when the system is not single-input single-output or a
///         band reaches the Nyquist frequency (discrete).
std::vector<double> filter_band_velocity_rms(const StateSpace& filter,
                                             const std::vector<ThirdOctaveBand>& bands);
std::vector<double> filter_band_velocity_rms(const DiscreteStateSpace& filter,
                                             const std::vector<ThirdOctaveBand>& bands);

/// Band RMS velocity from a one-sided acceleration PSD [(m/s²)²/Hz] sampled on a uniform grid
/// (e.g. welch_psd): Σ S_a(f_i) / (2π f_i)² Δf over the bins, each bin covering f_i ± Δf/2 and
/// counted by the fraction of it inside the band. @throws std::invalid_argument when the grid
/// is not uniform and increasing, sizes differ, or a band lies outside the grid.
std::vector<double> psd_band_velocity_rms(const Eigen::VectorXd& frequency_hz,
                                          const Eigen::VectorXd& acceleration_psd,
                                          const std::vector<ThirdOctaveBand>& bands);

}  // namespace flexloop::plant::lti
