// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/welch.hpp"

#include <unsupported/Eigen/FFT>

#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace flexloop::plant::lti {

namespace {

using Eigen::Index;

// Runs the segment loop once for one or two signals; `accumulate(k, X_k, Y_k)` gets the
// windowed spectra of each segment (Y = X when only x is given). Returns the segment count.
template <class Accumulate>
Index for_each_segment(const Eigen::VectorXd& x, const Eigen::VectorXd* y, double fs,
                       const WelchOptions& o, double& window_power, Accumulate accumulate) {
  const Index n = x.size(), len = o.segment_length;
  if (!(std::isfinite(fs) && fs > 0))
    throw std::invalid_argument("welch: sample rate must be finite and > 0 Hz");
  if (len < 2 || len > n)
    throw std::invalid_argument("welch: segment length " + std::to_string(len) +
                                " must be between 2 and the signal length " + std::to_string(n));
  if (!(o.overlap >= 0 && o.overlap < 1))
    throw std::invalid_argument("welch: overlap must be in [0, 1)");
  if (y && y->size() != n) throw std::invalid_argument("welch: x and y differ in length");

  std::vector<double> window(len);
  window_power = 0;
  for (Index i = 0; i < len; ++i) {
    window[i] = 0.5 * (1 - std::cos(2 * std::numbers::pi * i / len));
    window_power += window[i] * window[i];
  }
  const Index step = std::max<Index>(1, len - static_cast<Index>(std::lround(o.overlap * len)));
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<double> segment(len);
  std::vector<std::complex<double>> spectrum_x, spectrum_y;
  const auto transform = [&](const Eigen::VectorXd& s, Index start,
                             std::vector<std::complex<double>>& out) {
    const double mean = s.segment(start, len).mean();
    for (Index i = 0; i < len; ++i) segment[i] = window[i] * (s(start + i) - mean);
    fft.fwd(out, segment);
  };
  Index segments = 0;
  for (Index start = 0; start + len <= n; start += step, ++segments) {
    transform(x, start, spectrum_x);
    if (y) transform(*y, start, spectrum_y);
    for (Index k = 0; k <= len / 2; ++k)
      accumulate(k, spectrum_x[k], y ? spectrum_y[k] : spectrum_x[k]);
  }
  return segments;
}

// c_k / (fs Σw² segments): one-sided density scaling of the summed periodograms.
double scale(Index k, Index len, double fs, double window_power, Index segments) {
  const bool unpaired = k == 0 || (len % 2 == 0 && k == len / 2);
  return (unpaired ? 1.0 : 2.0) / (fs * window_power * static_cast<double>(segments));
}

Eigen::VectorXd frequencies(Index len, double fs) {
  return Eigen::VectorXd::LinSpaced(len / 2 + 1, 0, static_cast<double>(len / 2)) * (fs / len);
}

}  // namespace

PowerSpectrum welch_psd(const Eigen::VectorXd& x, double fs, const WelchOptions& o) {
  const Index len = o.segment_length;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(std::max<Index>(len / 2 + 1, 0));
  double window_power = 0;
  const Index segments = for_each_segment(
      x, nullptr, fs, o, window_power,
      [&](Index k, std::complex<double> xk, std::complex<double>) { sum(k) += std::norm(xk); });
  for (Index k = 0; k < sum.size(); ++k) sum(k) *= scale(k, len, fs, window_power, segments);
  return {frequencies(len, fs), sum, segments};
}

CrossSpectrum welch_csd(const Eigen::VectorXd& x, const Eigen::VectorXd& y, double fs,
                        const WelchOptions& o) {
  const Index len = o.segment_length;
  Eigen::VectorXcd sum = Eigen::VectorXcd::Zero(std::max<Index>(len / 2 + 1, 0));
  double window_power = 0;
  const Index segments = for_each_segment(
      x, &y, fs, o, window_power, [&](Index k, std::complex<double> xk, std::complex<double> yk) {
        sum(k) += std::conj(xk) * yk;
      });
  for (Index k = 0; k < sum.size(); ++k) sum(k) *= scale(k, len, fs, window_power, segments);
  return {frequencies(len, fs), sum, segments};
}

}  // namespace flexloop::plant::lti
