#include "controller/design/disk_margins.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>

#include "plant/lti/frequency_response.hpp"

namespace flexloop::controller::design {

namespace {

using Eigen::Index;

// S - I/2 = I/2 + H at the frequencies given.
class InputSensitivity {
 public:
  explicit InputSensitivity(const SampledLoopModel& loop) {
    const Index n = loop.A.rows(), nc = loop.command.rows();
    if (loop.A.cols() != n || loop.perturbation.rows() != n || loop.perturbation.cols() != nc ||
        loop.command.cols() != n || !(loop.dt > 0))
      throw std::invalid_argument("disk margins: the loop model's sizes do not close");
    h_.sys.A = loop.A;
    h_.sys.B = loop.perturbation;
    h_.sys.C = loop.command;
    h_.sys.D = Eigen::MatrixXd::Zero(nc, nc);
    for (Index i = 0; i < n; ++i) h_.sys.states.push_back("x" + std::to_string(i + 1));
    for (Index i = 0; i < nc; ++i) {
      h_.sys.inputs.push_back("e" + std::to_string(i + 1));
      h_.sys.outputs.push_back("u" + std::to_string(i + 1));
    }
    h_.dt = loop.dt;
  }

  std::vector<Eigen::MatrixXcd> centred(const std::vector<double>& f_hz) const {
    auto s = plant::lti::frequency_response(h_, f_hz);
    for (auto& m : s) m.diagonal().array() += 0.5;
    return s;
  }

  Index channels() const { return h_.sys.D.rows(); }
  double nyquist_hz() const { return 0.5 / h_.dt; }

 private:
  plant::lti::DiscreteStateSpace h_{{}, 0, plant::lti::DiscretisationMethod::kZeroOrderHold, 0, 0};
};

double largest_singular_value(const Eigen::MatrixXcd& m) {
  return Eigen::JacobiSVD<Eigen::MatrixXcd>(m).singularValues()(0);
}

// The peak of `measure` (of S - I/2 at one frequency) over the grid, refined by golden-section
// search in log f between the neighbours of the largest grid point.
template <class Measure>
std::pair<double, double> peak(const InputSensitivity& s, const std::vector<double>& f,
                               const std::vector<Eigen::MatrixXcd>& grid, Measure measure) {
  std::size_t best = 0;
  double best_value = -1;
  for (std::size_t k = 0; k < f.size(); ++k)
    if (const double v = measure(grid[k]); v > best_value) best_value = v, best = k;
  double lo = std::log(f[best == 0 ? 0 : best - 1]);
  double hi = std::log(f[std::min(best + 1, f.size() - 1)]);
  const double r = (std::sqrt(5.0) - 1) / 2;
  auto at = [&](double log_f) { return measure(s.centred({std::exp(log_f)})[0]); };
  double a = hi - r * (hi - lo), b = lo + r * (hi - lo), va = at(a), vb = at(b);
  for (int i = 0; i < 60 && hi - lo > 1e-12; ++i) {
    if (va > vb) {
      hi = b, b = a, vb = va, a = hi - r * (hi - lo), va = at(a);
    } else {
      lo = a, a = b, va = vb, b = lo + r * (hi - lo), vb = at(b);
    }
  }
  const double refined = std::max(va, vb);
  if (refined > best_value) return {refined, std::exp(va > vb ? a : b)};
  return {best_value, f[best]};
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
  const auto f = plant::lti::log_frequency_grid_hz(1e-6 * nyquist, nyquist, options.points);
  const auto grid = s.centred(f);
  InputDiskMargins r;
  for (Index i = 0; i < s.channels(); ++i)
    r.loops.push_back(margin_at_peak(
        peak(s, f, grid, [i](const Eigen::MatrixXcd& m) { return std::abs(m(i, i)); })));
  r.all_loops = margin_at_peak(peak(s, f, grid, largest_singular_value));
  return r;
}

}  // namespace flexloop::controller::design
