// SPDX-License-Identifier: BSD-3-Clause
// Welch PSD against known answers: a bin-centred sinusoid of amplitude A carries A²/2 in its
// three main-lobe bins (exact up to rounding: Parseval with the periodic Hann window), white
// noise of variance σ² has the level 2σ²/fs (within 5 standard errors, see below), and the
// cross spectrum of y = 3x is exactly 3 P_xx.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "plant/lti/welch.hpp"

using namespace flexloop::plant::lti;

TEST_CASE("welch: a bin-centred sinusoid puts A²/2 into its main lobe, nothing elsewhere") {
  const double fs = 1000, amplitude = 3, f0 = 50;
  const Eigen::Index n = 20000, len = 1000;  // resolution 1 Hz, f0 on bin 50
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i)
    x(i) = 0.7 + amplitude * std::sin(2 * std::numbers::pi * f0 * i / fs + 0.3);
  const auto p = welch_psd(x, fs, {.segment_length = len, .overlap = 0.5});
  CHECK(p.segments == 39);
  REQUIRE(p.frequency_hz.size() == len / 2 + 1);
  CHECK(p.frequency_hz(50) == Approx(50).epsilon(1e-15));
  const double df = fs / len;
  const double lobe = p.psd.segment(49, 3).sum() * df;
  const double rest = p.psd.sum() * df - lobe;
  CHECK(lobe == Approx(amplitude * amplitude / 2).epsilon(1e-12));
  CHECK(std::abs(rest) <= 1e-12 * lobe);                    // includes the removed mean 0.7
  CHECK(p.psd(50) == Approx(4 * p.psd(49)).epsilon(1e-9));  // Hann: 1/2, 1/4, 1/4 in amplitude
}

TEST_CASE("welch: white noise has the level 2 sigma^2 / fs") {
  // Averaging P_xx over the bins estimates the window-weighted mean square of the samples; with
  // a Hann window at 50 % overlap the weights are 3/4 + cos(4πn/L)/4, so the estimator's relative
  // standard error is sqrt(2 (19/18) / n) ≈ 1.45/sqrt(n); 1.5/sqrt(n) is used, and 5 of those.
  const double fs = 500, sigma = 2;
  const Eigen::Index n = 1 << 20, len = 1024;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0, sigma);
  Eigen::VectorXd x(n);
  for (auto& v : x) v = normal(rng);
  const auto p = welch_psd(x, fs, {.segment_length = len});
  const double level = p.psd.segment(4, len / 2 - 8).mean();
  INFO("level / (2 sigma^2 / fs) = " << level / (2 * sigma * sigma / fs));
  CHECK(std::abs(level / (2 * sigma * sigma / fs) - 1) <= 5 * 1.5 / std::sqrt(double(n)));
}

TEST_CASE("welch: cross spectrum of y = 3x is 3 P_xx, P_xx is the real cross spectrum of x, x") {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> normal;
  Eigen::VectorXd x(5000);
  for (auto& v : x) v = normal(rng);
  const WelchOptions o{.segment_length = 256, .overlap = 0.25};
  const auto pxx = welch_psd(x, 100, o);
  const auto pxy = welch_csd(x, 3 * x, 100, o);
  const auto self = welch_csd(x, x, 100, o);
  CHECK((pxy.csd - 3 * pxx.psd.cast<std::complex<double>>()).norm() <= 1e-12 * pxx.psd.norm());
  CHECK((self.csd.real() - pxx.psd).norm() <= 1e-14 * pxx.psd.norm());
  // conj(X) X is real; its computed imaginary part, re*im - im*re, is rounding (a fused
  // multiply-add rounds one product and not the other).
  CHECK(self.csd.imag().norm() <= 1e-15 * pxx.psd.norm());
  CHECK(pxy.segments == pxx.segments);
}

TEST_CASE("welch: rejects bad segment lengths, overlaps, rates and mismatched signals") {
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(100);
  CHECK_THROWS_WITH(welch_psd(x, 10, {.segment_length = 101}),
                    Catch::Contains("segment length 101"));
  CHECK_THROWS_AS(welch_psd(x, 10, {.segment_length = 1}), std::invalid_argument);
  CHECK_THROWS_AS(welch_psd(x, 10, {.segment_length = 10, .overlap = 1}), std::invalid_argument);
  CHECK_THROWS_AS(welch_psd(x, 0, {.segment_length = 10}), std::invalid_argument);
  CHECK_THROWS_WITH(welch_csd(x, Eigen::VectorXd::Ones(99), 10, {.segment_length = 10}),
                    Catch::Contains("differ in length"));
}
