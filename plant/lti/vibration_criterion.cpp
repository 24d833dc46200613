// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/vibration_criterion.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"

namespace flexloop::plant::lti {

namespace {

using Eigen::MatrixXd;
using numeric::kTwoPi;

struct CriterionName {
  VibrationCriterion criterion;
  const char* name;
  double band_velocity_rms;  // m/s
};
constexpr CriterionName kCriteria[] = {
    {VibrationCriterion::kVcA, "VC-A", 50e-6},   {VibrationCriterion::kVcB, "VC-B", 25e-6},
    {VibrationCriterion::kVcC, "VC-C", 12.5e-6}, {VibrationCriterion::kVcD, "VC-D", 6.25e-6},
    {VibrationCriterion::kVcE, "VC-E", 3.12e-6},
};

constexpr double kNominalCentresHz[] = {1,  1.25, 1.6, 2,  2.5, 3.15, 4,  5,  6.3, 8,
                                        10, 12.5, 16,  20, 25,  31.5, 40, 50, 63,  80};

void require_filter(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("floor filter: " + what);
}

// One SISO section x' = a x + b u, y = c x + d u appended after the chain (series connection:
// the section's input is the chain's output).
StateSpace series(const StateSpace& first, const MatrixXd& a, const MatrixXd& b, const MatrixXd& c,
                  double d) {
  const auto n1 = first.nx(), n2 = a.rows();
  StateSpace s;
  s.A = MatrixXd::Zero(n1 + n2, n1 + n2);
  s.A.topLeftCorner(n1, n1) = first.A;
  s.A.bottomLeftCorner(n2, n1) = b * first.C;
  s.A.bottomRightCorner(n2, n2) = a;
  s.B.resize(n1 + n2, 1);
  s.B << first.B, b * first.D;
  s.C.resize(1, n1 + n2);
  s.C << d * first.C, c;
  s.D = d * first.D;
  return s;
}

// (s + z)/(s + p) = 1 + (z - p)/(s + p).
StateSpace append_pole_zero(const StateSpace& chain, double z, double p) {
  return series(chain, MatrixXd::Constant(1, 1, -p), MatrixXd::Ones(1, 1),
                MatrixXd::Constant(1, 1, z - p), 1);
}

// Butterworth second order at w, controllable canonical form x = (y, y'):
// low-pass  w²/(s² + √2 w s + w²):  y = w² x1;   high-pass  s²/(...) = 1 - (√2 w s + w²)/(...).
StateSpace append_butterworth(const StateSpace& chain, double w, bool high_pass) {
  MatrixXd a(2, 2), b(2, 1), c(1, 2);
  a << 0, 1, -w * w, -std::numbers::sqrt2 * w;
  b << 0, 1;
  if (high_pass)
    c << -w * w, -std::numbers::sqrt2 * w;
  else
    c << w * w, 0;
  return series(chain, a, b, c, high_pass ? 1 : 0);
}

// Simpson's rule in u = ln f over [ln lo, ln hi]: ∫ g(f) df = ∫ g(e^u) e^u du.
double integrate_log(const std::function<std::vector<double>(const std::vector<double>&)>& g,
                     double lo, double hi) {
  constexpr int kIntervals = 64;
  const double h = (std::log(hi) - std::log(lo)) / kIntervals;
  std::vector<double> f(kIntervals + 1);
  for (int i = 0; i <= kIntervals; ++i) f[i] = std::exp(std::log(lo) + i * h);
  const auto values = g(f);
  double sum = 0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double w = (i == 0 || i == kIntervals) ? 1 : (i % 2 ? 4 : 2);
    sum += w * values[i] * f[i];
  }
  return sum * h / 3;
}

// Band RMS velocity of a one-sided acceleration PSD given as a function of frequency.
std::vector<double> band_velocity_rms(
    const std::function<std::vector<double>(const std::vector<double>&)>& acceleration_psd,
    const std::vector<ThirdOctaveBand>& bands) {
  std::vector<double> rms;
  for (const auto& band : bands) {
    const auto velocity_psd = [&](const std::vector<double>& f) {
      auto s = acceleration_psd(f);
      for (std::size_t i = 0; i < f.size(); ++i) s[i] /= (kTwoPi * f[i]) * (kTwoPi * f[i]);
      return s;
    };
    rms.push_back(std::sqrt(integrate_log(velocity_psd, band.lower_hz, band.upper_hz)));
  }
  return rms;
}

void require_siso(const StateSpace& s) {
  s.validate();
  if (s.nu() != 1 || s.ny() != 1)
    throw std::invalid_argument(
        "filter_band_velocity_rms: the filter must have one input and one "
        "output, has " +
        std::to_string(s.nu()) + " and " + std::to_string(s.ny()));
}

}  // namespace

VibrationCriterion parse_vibration_criterion(const std::string& name) {
  for (const auto& c : kCriteria)
    if (name == c.name) return c.criterion;
  throw std::invalid_argument("unknown vibration criterion '" + name +
                              "' (expected VC-A, VC-B, VC-C, VC-D or VC-E)");
}

std::string to_string(VibrationCriterion criterion) {
  for (const auto& c : kCriteria)
    if (c.criterion == criterion) return c.name;
  throw std::invalid_argument("to_string: invalid VibrationCriterion");
}

double criterion_band_velocity_rms(VibrationCriterion criterion) {
  for (const auto& c : kCriteria)
    if (c.criterion == criterion) return c.band_velocity_rms;
  throw std::invalid_argument("criterion_band_velocity_rms: invalid VibrationCriterion");
}

std::vector<ThirdOctaveBand> criterion_bands() {
  std::vector<ThirdOctaveBand> bands;
  int n = 0;
  for (const double nominal : kNominalCentresHz) {
    const double centre = std::pow(10.0, n++ / 10.0);
    bands.push_back(
        {nominal, centre, centre * std::pow(10.0, -0.05), centre * std::pow(10.0, 0.05)});
  }
  return bands;
}

namespace {

StateSpace designed_floor_filter(double band_velocity_rms, const FloorFilterOptions& o) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  require_filter(positive(band_velocity_rms), "band velocity RMS must be finite and > 0 m/s");
  require_filter(positive(o.approximation_low_hz) && positive(o.approximation_high_hz) &&
                     positive(o.high_pass_hz) && positive(o.low_pass_hz),
                 "frequencies must be finite and > 0 Hz");
  require_filter(o.approximation_low_hz < o.approximation_high_hz,
                 "approximation_low_hz must be below approximation_high_hz");
  require_filter(o.pole_zero_pairs >= 1, "pole_zero_pairs must be >= 1");

  const double wb = kTwoPi * o.approximation_low_hz, wh = kTwoPi * o.approximation_high_hz;
  const double ratio = wh / wb;
  const int m = o.pole_zero_pairs;

  StateSpace h{MatrixXd::Zero(0, 0),
               MatrixXd::Zero(0, 1),
               MatrixXd::Zero(1, 0),
               MatrixXd::Ones(1, 1),
               {},
               {},
               {}};
  h = append_butterworth(h, kTwoPi * o.high_pass_hz, /*high_pass=*/true);
  for (int k = 1; k <= m; ++k)
    h = append_pole_zero(h, wb * std::pow(ratio, (k - 0.75) / m),
                         wb * std::pow(ratio, (k - 0.25) / m));
  h = append_butterworth(h, kTwoPi * o.low_pass_hz, /*high_pass=*/false);
  for (Eigen::Index i = 0; i < h.nx(); ++i) h.states.push_back("floor_filter_" + std::to_string(i));
  h.inputs = {"white_noise"};
  h.outputs = {"floor_acceleration"};

  // In band the product is ≈ (s/ωh)^(1/2); the target is |H|² = π K ω (see the header).
  const double k_velocity = band_velocity_rms * band_velocity_rms / (0.1 * std::log(10.0));
  h.C *= std::sqrt(std::numbers::pi * k_velocity * wh);

  // Centre the remaining band errors: scale by the geometric mean of the extreme ratios.
  const auto rms = filter_band_velocity_rms(h, criterion_bands());
  const auto [lo, hi] = std::minmax_element(rms.begin(), rms.end());
  h.C *= band_velocity_rms / std::sqrt(*lo * *hi);
  return h;
}

}  // namespace

// The design integrates the filter's response over every third-octave band (a few ms): a
// campaign asks for the same floor at each of its samples, twice. The last design is kept, per
// thread, and given again for the same arguments, bit for bit.
StateSpace design_floor_filter(double band_velocity_rms, const FloorFilterOptions& o) {
  struct Last {
    double v;
    FloorFilterOptions o;
    StateSpace filter;
  };
  thread_local std::optional<Last> last;
  const auto same = [&](const Last& l) {
    return l.v == band_velocity_rms && l.o.approximation_low_hz == o.approximation_low_hz &&
           l.o.approximation_high_hz == o.approximation_high_hz &&
           l.o.pole_zero_pairs == o.pole_zero_pairs && l.o.high_pass_hz == o.high_pass_hz &&
           l.o.low_pass_hz == o.low_pass_hz;
  };
  if (!last || !same(*last))
    last = Last{band_velocity_rms, o, designed_floor_filter(band_velocity_rms, o)};
  return last->filter;
}

Eigen::MatrixXd floor_motion_outputs(const StateSpace& filter) {
  require_siso(filter);
  const Eigen::PartialPivLU<MatrixXd> lu(filter.A);
  require_filter(filter.nx() > 0 && lu.rcond() > 1e-12, "the floor filter's A must be invertible");
  const Eigen::PartialPivLU<MatrixXd> lut(filter.A.transpose());
  MatrixXd m(2, filter.nx());
  const Eigen::VectorXd cv = lut.solve(Eigen::VectorXd(filter.C.row(0).transpose()));  // A^-T C^T
  m.row(0) = cv.transpose();                                                           // C A^-1
  m.row(1) = lut.solve(cv).transpose();                                                // C A^-2
  // H(s) = C (sI - A)^-1 B must vanish twice at s = 0: C A^-1 B = 0 and C A^-2 B = 0 (to
  // rounding, relative to |C| |A^-1|^k |B|).
  const double inv = 1.0 / (lu.rcond() * induced_norm_1(filter.A));  // ~ |A^-1|_1
  const double cb = filter.C.norm() * filter.B.norm();
  require_filter(filter.D.norm() == 0 && std::abs((m.row(0) * filter.B)(0, 0)) <= 1e-9 * cb * inv &&
                     std::abs((m.row(1) * filter.B)(0, 0)) <= 1e-9 * cb * inv * inv,
                 "the floor filter must have a double zero at s = 0 (a stationary displacement)");
  return m;
}

DiscreteStateSpace discretise_floor_filter(const StateSpace& filter, double dt) {
  const MatrixXd motion = floor_motion_outputs(filter);
  auto d = discretise(filter, {.method = DiscretisationMethod::kZeroOrderHold, .dt = dt});
  d.sys.B /= std::sqrt(dt);
  // Sample-mean acceleration: a_k = (v_{k+1} - v_k) / dt, v = C A^-1 x (see the header).
  const MatrixXd cv = motion.row(0);
  d.sys.C = cv * (d.sys.A - MatrixXd::Identity(d.sys.A.rows(), d.sys.A.cols())) / dt;
  d.sys.D = cv * d.sys.B / dt;
  return d;
}

std::vector<double> filter_band_velocity_rms(const StateSpace& filter,
                                             const std::vector<ThirdOctaveBand>& bands) {
  require_siso(filter);
  return band_velocity_rms(
      [&](const std::vector<double>& f) {
        const auto g = frequency_response(filter, f);
        std::vector<double> s;
        for (const auto& gi : g) s.push_back(2 * std::norm(gi(0, 0)));
        return s;
      },
      bands);
}

std::vector<double> filter_band_velocity_rms(const DiscreteStateSpace& filter,
                                             const std::vector<ThirdOctaveBand>& bands) {
  require_siso(filter.sys);
  for (const auto& band : bands)
    if (band.upper_hz >= 0.5 / filter.dt)
      throw std::invalid_argument("filter_band_velocity_rms: band " +
                                  std::to_string(band.nominal_hz) +
                                  " Hz reaches the Nyquist frequency");
  return band_velocity_rms(
      [&](const std::vector<double>& f) {
        const auto g = frequency_response(filter, f);
        std::vector<double> s;
        for (const auto& gi : g) s.push_back(2 * filter.dt * std::norm(gi(0, 0)));
        return s;
      },
      bands);
}

std::vector<double> psd_band_velocity_rms(const Eigen::VectorXd& frequency_hz,
                                          const Eigen::VectorXd& acceleration_psd,
                                          const std::vector<ThirdOctaveBand>& bands) {
  const auto n = frequency_hz.size();
  if (n < 2 || acceleration_psd.size() != n)
    throw std::invalid_argument(
        "psd_band_velocity_rms: need at least two bins and as many PSD "
        "values as frequencies");
  const double df = frequency_hz(1) - frequency_hz(0);
  for (Eigen::Index i = 1; i < n; ++i)
    if (!(df > 0) || std::abs(frequency_hz(i) - frequency_hz(0) - i * df) > 1e-9 * i * df)
      throw std::invalid_argument(
          "psd_band_velocity_rms: frequencies must be uniform and increasing");
  std::vector<double> rms;
  for (const auto& band : bands) {
    if (band.lower_hz < frequency_hz(0) || band.upper_hz > frequency_hz(n - 1))
      throw std::invalid_argument("psd_band_velocity_rms: band " + std::to_string(band.nominal_hz) +
                                  " Hz lies outside the PSD's frequencies");
    double power = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double f = frequency_hz(i);
      const double overlap =
          std::min(f + df / 2, band.upper_hz) - std::max(f - df / 2, band.lower_hz);
      if (overlap > 0 && f > 0)
        power += acceleration_psd(i) / ((kTwoPi * f) * (kTwoPi * f)) * overlap;
    }
    rms.push_back(std::sqrt(power));
  }
  return rms;
}

}  // namespace flexloop::plant::lti
