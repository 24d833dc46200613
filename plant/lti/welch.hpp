// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Welch's averaged, modified periodogram (Welch, IEEE Trans. Audio Electroacoust. 15 (1967)):
// the signal is cut into segments of L samples that overlap by a fraction of L (the tail that
// does not fill a segment is dropped), each segment's mean is removed, it is multiplied by the
// periodic Hann window w_n = (1 - cos(2πn/L))/2 and transformed (Eigen's FFT, kissfft):
//   X_k = Σ_n w_n x_n e^{-j2πkn/L},   f_k = k fs / L,   k = 0 .. L/2.
// One-sided densities, averaged over the segments (the same scaling as scipy.signal.welch with
// window="hann", detrend="constant", scaling="density"):
//   P_xx(f_k) = c_k |X_k|² / (fs Σ w_n²),   P_xy(f_k) = c_k conj(X_k) Y_k / (fs Σ w_n²),
//   c_k = 1 at DC and (even L) at Nyquist, 2 elsewhere,
// so Σ_k P_xx(f_k) fs/L is the signal's mean-square value (without its DC) and P_xy/P_xx
// estimates the transfer function from x to y (H1). Units: [x]²/Hz and [x][y]/Hz.
// A sinusoid of amplitude A whose frequency lies on a bin puts A²/2 into that bin and its two
// neighbours (Hann main lobe); white noise of variance σ² has P_xx = 2σ²/fs.
#include <Eigen/Dense>

namespace flexloop::plant::lti {

struct WelchOptions {
  Eigen::Index segment_length;  ///< L, samples per segment (>= 2); resolution fs/L
  double overlap = 0.5;         ///< fraction of L shared by consecutive segments, in [0, 1)
};

struct PowerSpectrum {
  Eigen::VectorXd frequency_hz;  ///< f_k, k = 0 .. L/2
  Eigen::VectorXd psd;           ///< P_xx(f_k), one-sided
  Eigen::Index segments;         ///< how many segments were averaged
};

struct CrossSpectrum {
  Eigen::VectorXd frequency_hz;
  Eigen::VectorXcd csd;  ///< P_xy(f_k), one-sided
  Eigen::Index segments;
};

/// @throws std::invalid_argument unless fs > 0 (finite), 2 <= L <= x.size() and
///         0 <= overlap < 1.
PowerSpectrum welch_psd(const Eigen::VectorXd& x, double sample_rate_hz,
                        const WelchOptions& options);

/// Same exceptions, and when x and y differ in length.
CrossSpectrum welch_csd(const Eigen::VectorXd& x, const Eigen::VectorXd& y, double sample_rate_hz,
                        const WelchOptions& options);

}  // namespace flexloop::plant::lti
