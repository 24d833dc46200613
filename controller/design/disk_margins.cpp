// SPDX-License-Identifier: BSD-3-Clause
#include "controller/design/disk_margins.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "numeric/constants.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/schur_transfer.hpp"

namespace flexloop::controller::design {

namespace {

using Eigen::Index;

// S - I/2 = I/2 + H at one frequency, two ways: on H's Schur form (plant/lti/schur_transfer.hpp,
// half the cost a point) for the search over the grid, and on its Hessenberg form
// (plant/lti/frequency_response.hpp) for the values a margin is read from, as analyse always has.
class InputSensitivity {
 public:
  explicit InputSensitivity(const SampledLoopModel& loop)
      : channels_(loop.command.rows()),
        exact_(transfer(loop)),
        searched_(loop.A, loop.perturbation, loop.command, 1.0),
        dt_(loop.dt) {}

  // For the search: at each frequency given.
  std::vector<Eigen::MatrixXcd> searched(const std::vector<double>& f_hz) const {
    std::vector<Eigen::MatrixXcd> s;
    s.reserve(f_hz.size());
    for (const double f : f_hz) s.push_back(searched(f));
    return s;
  }
  Eigen::MatrixXcd searched(double f_hz) const {
    require_finite(f_hz);
    // z - 1 without cancellation: e^{j theta} - 1 = -2 sin^2(theta / 2) + j sin(theta).
    const double theta = numeric::kTwoPi * f_hz * dt_, half = std::sin(theta / 2);
    Eigen::MatrixXcd m;
    if (!searched_.evaluate({-2 * half * half, std::sin(theta)}, m)) return exact(f_hz);
    m.diagonal().array() += 0.5;
    return m;
  }
  // As frequency_response of the discrete system: z = e^{j 2 pi f dt}.
  Eigen::MatrixXcd exact(double f_hz) const {
    require_finite(f_hz);
    Eigen::MatrixXcd m;
    const auto r = exact_.evaluate(std::polar(1.0, numeric::kTwoPi * f_hz * dt_), m);
    if (r != plant::lti::TransferFunction::Point::kFinite) {
      std::ostringstream what;
      what.precision(17);
      what << "frequency_response: the point for " << f_hz << " Hz is "
           << (r == plant::lti::TransferFunction::Point::kEigenvalue
                   ? "an eigenvalue of A (the response is infinite)"
                   : "next to an eigenvalue of A (the response is not finite)");
      throw std::domain_error(what.str());
    }
    m.diagonal().array() += 0.5;
    return m;
  }

  Index channels() const { return channels_; }
  double nyquist_hz() const { return 0.5 / dt_; }
  // The frequencies of the loop's complex poles (upper half plane): where a lightly damped pole
  // raises a peak narrower than the grid's spacing, the grid then holds its top.
  Eigen::VectorXd pole_frequencies_hz() const {
    const Eigen::VectorXcd poles = searched_.poles();
    Eigen::VectorXd f = Eigen::VectorXd::Constant(poles.size(), std::nan(""));
    for (Index k = 0; k < poles.size(); ++k)
      if (poles(k).imag() > 0) f(k) = std::arg(poles(k)) / (numeric::kTwoPi * dt_);
    return f;
  }

 private:
  static void require_finite(double f_hz) {
    if (!std::isfinite(f_hz))
      throw std::invalid_argument("disk margins: a frequency is not finite");
  }
  static void require_sizes(const SampledLoopModel& loop) {
    const Index n = loop.A.rows(), nc = loop.command.rows();
    if (loop.A.cols() != n || loop.perturbation.rows() != n || loop.perturbation.cols() != nc ||
        loop.command.cols() != n || !(loop.dt > 0))
      throw std::invalid_argument("disk margins: the loop model's sizes do not close");
  }
  // H: the perturbation added to the command -> the command.
  static plant::lti::TransferFunction transfer(const SampledLoopModel& loop) {
    require_sizes(loop);
    const Index n = loop.A.rows(), nc = loop.command.rows();
    plant::lti::StateSpace h{
        loop.A, loop.perturbation, loop.command, Eigen::MatrixXd::Zero(nc, nc), {}, {}, {}};
    for (Index i = 0; i < n; ++i) h.states.push_back("x" + std::to_string(i + 1));
    for (Index i = 0; i < nc; ++i) {
      h.inputs.push_back("e" + std::to_string(i + 1));
      h.outputs.push_back("u" + std::to_string(i + 1));
    }
    return plant::lti::TransferFunction(h);
  }

  Index channels_;
  plant::lti::TransferFunction exact_;
  plant::lti::SchurTransfer searched_;
  double dt_;
};

// sigma_max by the SVD: for the value a margin is read from. On a row-major copy: an SVD type no
// other translation unit instantiates, so every program that links this code runs this one copy
// of its inline templates. JacobiSVD<MatrixXcd> is also plant/lti/modal_form.cpp's: each program
// ran the copy its linker kept, and the Python module's and `flexloop`'s differed (nm -S) and
// rounded differently in the last bits (doc/python.md).
double largest_singular_value_by_svd(const Eigen::MatrixXcd& m) {
  using RowMajorXcd =
      Eigen::Matrix<std::complex<double>, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::JacobiSVD<RowMajorXcd>(RowMajorXcd(m)).singularValues()(0);
}

// sigma_max at each grid point that can hold the grid's largest, -1 elsewhere: the largest
// column norm <= sigma_max <= min(Frobenius norm, sqrt(||M||_1 ||M||_inf)), so a point whose upper
// bound lies below some point's largest column norm cannot (the factor covers their rounding).
// S - I/2 is near I/2 away from the loop's crossover, where the second bound is the tight one.
std::vector<double> largest_singular_values_near_peak(const std::vector<Eigen::MatrixXcd>& grid) {
  double floor = 0;
  for (const auto& m : grid) floor = std::max(floor, m.colwise().norm().maxCoeff());
  std::vector<double> v(grid.size(), -1);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const Eigen::MatrixXd a = grid[k].cwiseAbs();
    const double bound = std::min(
        grid[k].norm(), std::sqrt(a.colwise().sum().maxCoeff() * a.rowwise().sum().maxCoeff()));
    if (bound * (1 + 1e-9) >= floor) v[k] = plant::lti::largest_singular_value(grid[k]);
  }
  return v;
}

// The peak of `measure` (of S - I/2 at one frequency) over the grid (its values there given),
// refined by golden-section search in log f between the neighbours of the largest grid point;
// the peak's value is `exact` of the exact S - I/2, the larger at the grid's best point and at
// the point the refinement settles on.
template <class Measure, class Exact>
std::pair<double, double> peak(const InputSensitivity& s, const std::vector<double>& f,
                               const std::vector<double>& values, Measure measure, Exact exact) {
  std::size_t best = 0;
  double best_value = -1;
  for (std::size_t k = 0; k < f.size(); ++k)
    if (const double v = values[k]; v > best_value) best_value = v, best = k;
  double lo = std::log(f[best == 0 ? 0 : best - 1]);
  double hi = std::log(f[std::min(best + 1, f.size() - 1)]);
  const double r = (std::sqrt(5.0) - 1) / 2;
  auto at = [&](double log_f) { return measure(s.searched(std::exp(log_f))); };
  double a = hi - r * (hi - lo), b = lo + r * (hi - lo), va = at(a), vb = at(b);
  for (int i = 0; i < 60 && hi - lo > 1e-12; ++i) {
    if (va > vb) {
      hi = b, b = a, vb = va, a = hi - r * (hi - lo), va = at(a);
    } else {
      lo = a, a = b, va = vb, b = lo + r * (hi - lo), vb = at(b);
    }
  }
  // The larger of the two candidates, each valued exactly: where the peak is flat (at an end
  // of the grid) the searched values' rounding must not pick the lower one.
  const double f_refined = std::exp(va > vb ? a : b);
  const double at_refined = exact(s.exact(f_refined)), at_grid = exact(s.exact(f[best]));
  return at_refined > at_grid ? std::pair{at_refined, f_refined} : std::pair{at_grid, f[best]};
}

DiskMargin margin_at_peak(std::pair<double, double> p) {
  DiskMargin m = disk_margin_of(1.0 / p.first);
  m.frequency_hz = p.second;
  return m;
}

}  // namespace

DiskMargin disk_margin_of(double alpha) {
  DiskMargin m;
  m.alpha = alpha;
  m.gain_low = std::max(0.0, (2 - alpha) / (2 + alpha));
  m.gain_high = alpha < 2 ? (2 + alpha) / (2 - alpha) : std::numeric_limits<double>::infinity();
  m.phase_deg = 2 * std::atan(alpha / 2) * 180 / M_PI;
  return m;
}

InputDiskMargins input_disk_margins(const SampledLoopModel& loop,
                                    const DiskMarginOptions& options) {
  if (options.points < 16) throw std::invalid_argument("disk margins: need at least 16 points");
  const InputSensitivity s(loop);
  const double nyquist = s.nyquist_hz();
  const auto f = plant::lti::with_resonances(
      plant::lti::log_frequency_grid_hz(1e-6 * nyquist, nyquist, options.points),
      s.pole_frequencies_hz());
  const auto grid = s.searched(f);
  InputDiskMargins r;
  std::vector<double> values(f.size());
  for (Index i = 0; i < s.channels(); ++i) {
    const auto loop_i = [i](const Eigen::MatrixXcd& m) { return std::abs(m(i, i)); };
    for (std::size_t k = 0; k < f.size(); ++k) values[k] = loop_i(grid[k]);
    r.loops.push_back(margin_at_peak(peak(s, f, values, loop_i, loop_i)));
  }
  r.all_loops =
      margin_at_peak(peak(s, f, largest_singular_values_near_peak(grid),
                          plant::lti::largest_singular_value, largest_singular_value_by_svd));
  return r;
}

}  // namespace flexloop::controller::design
