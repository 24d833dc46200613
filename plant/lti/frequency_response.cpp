// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/frequency_response.hpp"

#include <Eigen/Jacobi>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "numeric/constants.hpp"

namespace flexloop::plant::lti {

namespace {
using cd = std::complex<double>;
using numeric::kTwoPi;

std::string to_string_g(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
}  // namespace

std::vector<double> log_frequency_grid_hz(double f_min_hz, double f_max_hz, int points) {
  if (!(std::isfinite(f_min_hz) && std::isfinite(f_max_hz) && f_min_hz > 0.0 &&
        f_max_hz > f_min_hz))
    throw std::invalid_argument(
        "log_frequency_grid_hz: need 0 < f_min < f_max, got f_min = " + to_string_g(f_min_hz) +
        " Hz, f_max = " + to_string_g(f_max_hz) + " Hz");
  if (points < 2)
    throw std::invalid_argument("log_frequency_grid_hz: need at least 2 points, got " +
                                std::to_string(points));
  const double l0 = std::log10(f_min_hz);
  const double step = (std::log10(f_max_hz) - l0) / (points - 1);
  std::vector<double> f(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) f[static_cast<std::size_t>(i)] = std::pow(10.0, l0 + i * step);
  // pow/log10 round; the caller asked for these exact end points.
  f.front() = f_min_hz;
  f.back() = f_max_hz;
  return f;
}

std::vector<double> with_resonances(std::vector<double> grid_hz,
                                    const Eigen::VectorXd& resonances_hz) {
  if (grid_hz.empty()) return grid_hz;
  const double lo = grid_hz.front(), hi = grid_hz.back();
  for (const double f : resonances_hz)
    if (std::isfinite(f) && f > lo && f < hi) grid_hz.push_back(f);
  std::sort(grid_hz.begin(), grid_hz.end());
  grid_hz.erase(std::unique(grid_hz.begin(), grid_hz.end()), grid_hz.end());
  return grid_hz;
}

std::vector<double> unwrapped_phase_deg(const std::vector<std::complex<double>>& g) {
  constexpr double kDegPerRad = 180.0 / std::numbers::pi;
  std::vector<double> ph(g.size());
  double offset = 0.0, prev = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double p = std::arg(g[i]) * kDegPerRad;
    if (std::isfinite(prev)) {
      while (p + offset - prev > 180.0) offset -= 360.0;
      while (p + offset - prev < -180.0) offset += 360.0;
    }
    ph[i] = std::isfinite(p) ? p + offset : std::numeric_limits<double>::quiet_NaN();
    if (std::isfinite(ph[i])) prev = ph[i];
  }
  // Whole turns off so that the curve starts in (-180, 180]: a phase that begins near -720 reads
  // as the same physics, shifted out of the range engineers look in.
  const auto first = std::find_if(ph.begin(), ph.end(), [](double v) { return std::isfinite(v); });
  if (first != ph.end()) {
    const double turns = std::ceil((*first - 180.0) / 360.0);
    for (double& v : ph) v -= 360.0 * turns;
  }
  return ph;
}

Eigen::VectorXd balancing_scaling(const Eigen::MatrixXd& A) {
  if (A.rows() != A.cols()) throw std::invalid_argument("balancing_scaling: A must be square");
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd a = A;
  Eigen::VectorXd t = Eigen::VectorXd::Ones(n);
  // Powers of two only, so the similarity is exact; the bounds keep scale factors finite.
  constexpr double kRadix = 2.0, kFactor = 0.95, kBig = 1e150, kSmall = 1e-150;
  bool changed = true;
  for (int sweep = 0; changed && sweep < 100; ++sweep) {
    changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      // Off-diagonal 2-norms of column and row i.
      double c = std::sqrt(std::max(0.0, a.col(i).squaredNorm() - a(i, i) * a(i, i)));
      double r = std::sqrt(std::max(0.0, a.row(i).squaredNorm() - a(i, i) * a(i, i)));
      if (!(c > 0.0) || !(r > 0.0)) continue;  // decoupled row or column: nothing to balance
      const double s = c + r;
      double f = 1.0;
      while (c < r / kRadix && f < kBig) {
        f *= kRadix;
        c *= kRadix;
        r /= kRadix;
      }
      while (c / kRadix >= r && f > kSmall) {
        f /= kRadix;
        c /= kRadix;
        r *= kRadix;
      }
      if (c + r >= kFactor * s) continue;  // not worth it: avoids cycling
      t(i) *= f;
      a.row(i) /= f;
      a.col(i) *= f;
      changed = true;
    }
  }
  return t;
}

TransferFunction::TransferFunction(const StateSpace& sys, const FrequencyResponseOptions& options) {
  sys.validate();
  D_ = sys.D.cast<cd>();
  if (sys.nx() == 0) return;  // static gain
  // Similarity A_b = T^-1 A T with exact power-of-two T.
  Eigen::MatrixXd Ab = sys.A, Bb = sys.B, Cb = sys.C;
  if (options.balance) {
    const Eigen::VectorXd t = balancing_scaling(sys.A);
    Ab = t.cwiseInverse().asDiagonal() * sys.A * t.asDiagonal();
    Bb = t.cwiseInverse().asDiagonal() * sys.B;
    Cb = sys.C * t.asDiagonal();
  }
  // A_b = Q H Q^T once.
  const Eigen::HessenbergDecomposition<Eigen::MatrixXd> hess(Ab);
  const Eigen::MatrixXd Q = hess.matrixQ();
  H_ = Eigen::MatrixXd(hess.matrixH()).cast<cd>();
  B_ = (Q.transpose() * Bb).cast<cd>();
  C_ = (Cb * Q).cast<cd>();
}

TransferFunction::Point TransferFunction::evaluate(cd s, Eigen::MatrixXcd& g) const {
  const Eigen::Index n = H_.rows();
  if (n == 0) {
    g = D_;
    return Point::kFinite;
  }
  Eigen::MatrixXcd W = -H_, X = B_;
  W.diagonal().array() += s;
  // Givens QR of the Hessenberg matrix: one rotation per subdiagonal entry, applied to the
  // trailing columns only (the leading ones are already zero in both rows).
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    Eigen::JacobiRotation<cd> r;
    r.makeGivens(W(k, k), W(k + 1, k));
    W.rightCols(n - k).applyOnTheLeft(k, k + 1, r.adjoint());
    X.applyOnTheLeft(k, k + 1, r.adjoint());
    W(k + 1, k) = 0.0;
  }
  if ((W.diagonal().array() == cd(0.0, 0.0)).any()) return Point::kEigenvalue;
  W.triangularView<Eigen::Upper>().solveInPlace(X);
  g = D_;
  if (g.rows() > 0 && g.cols() > 0) g.noalias() += C_ * X;
  return g.allFinite() ? Point::kFinite : Point::kNextToEigenvalue;
}

Eigen::MatrixXcd TransferFunction::at(cd p) const {
  Eigen::MatrixXcd g;
  const Point r = evaluate(p, g);
  if (r == Point::kFinite) return g;
  throw std::domain_error("transfer function: " + to_string_g(p.real()) + "+" +
                          to_string_g(p.imag()) + "j is " +
                          (r == Point::kEigenvalue ? "an eigenvalue of A (the response is infinite)"
                                                   : "next to an eigenvalue of A (the response is "
                                                     "not finite)"));
}

namespace {

// C (pI - A)^-1 B + D at each point; `where(i)` names point i in the messages.
template <class Where>
std::vector<Eigen::MatrixXcd> evaluate(const StateSpace& sys, const std::vector<cd>& points,
                                       const FrequencyResponseOptions& options, Where where) {
  const TransferFunction tf(sys, options);
  std::vector<Eigen::MatrixXcd> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto r = tf.evaluate(points[i], out[i]);
    if (r == TransferFunction::Point::kEigenvalue)
      throw std::domain_error(where(i) + " is an eigenvalue of A (the response is infinite)");
    if (r == TransferFunction::Point::kNextToEigenvalue)
      throw std::domain_error(where(i) +
                              " is next to an eigenvalue of A (the response is not finite)");
  }
  return out;
}

}  // namespace

std::vector<Eigen::MatrixXcd> transfer_at(const StateSpace& sys,
                                          const std::vector<std::complex<double>>& points,
                                          const FrequencyResponseOptions& options) {
  for (const cd& p : points)
    if (!std::isfinite(p.real()) || !std::isfinite(p.imag()))
      throw std::invalid_argument("transfer_at: evaluation point is not finite");
  return evaluate(sys, points, options, [&](std::size_t i) {
    return "transfer_at: " + to_string_g(points[i].real()) + "+" + to_string_g(points[i].imag()) +
           "j";
  });
}

namespace {

// Continuous (p = j 2 pi f) or discrete (p = e^{j 2 pi f dt}) response, messages in Hz.
template <class Point>
std::vector<Eigen::MatrixXcd> response_at(const StateSpace& sys,
                                          const std::vector<double>& freqs_hz,
                                          const FrequencyResponseOptions& options, Point point) {
  std::vector<cd> points;
  points.reserve(freqs_hz.size());
  for (double f : freqs_hz) {
    if (!std::isfinite(f))
      throw std::invalid_argument("frequency_response: frequency " + to_string_g(f) +
                                  " Hz is not finite");
    points.push_back(point(f));
  }
  return evaluate(sys, points, options, [&](std::size_t i) {
    return "frequency_response: the point for " + to_string_g(freqs_hz[i]) + " Hz";
  });
}

}  // namespace

std::vector<Eigen::MatrixXcd> frequency_response(const StateSpace& sys,
                                                 const std::vector<double>& freqs_hz,
                                                 const FrequencyResponseOptions& options) {
  return response_at(sys, freqs_hz, options, [](double f) { return cd(0.0, kTwoPi * f); });
}

std::vector<Eigen::MatrixXcd> frequency_response(const DiscreteStateSpace& sys,
                                                 const std::vector<double>& freqs_hz,
                                                 const FrequencyResponseOptions& options) {
  return response_at(sys.sys, freqs_hz, options,
                     [&](double f) { return std::polar(1.0, kTwoPi * f * sys.dt); });
}

double largest_singular_value(const Eigen::MatrixXcd& G) {
  if (G.size() == 0) return 0;
  const Eigen::MatrixXcd gram =
      G.rows() < G.cols() ? Eigen::MatrixXcd(G * G.adjoint()) : Eigen::MatrixXcd(G.adjoint() * G);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(gram, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0));
}

Eigen::MatrixXd singular_values(const std::vector<Eigen::MatrixXcd>& G) {
  if (G.empty()) return Eigen::MatrixXd(0, 0);
  const Eigen::Index rows = G.front().rows(), cols = G.front().cols();
  Eigen::MatrixXd sigma(static_cast<Eigen::Index>(G.size()), std::min(rows, cols));
  for (std::size_t k = 0; k < G.size(); ++k) {
    if (G[k].rows() != rows || G[k].cols() != cols)
      throw std::invalid_argument("singular_values: matrix " + std::to_string(k) + " is " +
                                  std::to_string(G[k].rows()) + "x" + std::to_string(G[k].cols()) +
                                  ", the first is " + std::to_string(rows) + "x" +
                                  std::to_string(cols));
    if (sigma.cols() == 0) continue;
    // BDCSVD returns the singular values sorted in decreasing order.
    const Eigen::BDCSVD<Eigen::MatrixXcd> svd(G[k]);
    sigma.row(static_cast<Eigen::Index>(k)) = svd.singularValues().transpose();
  }
  return sigma;
}

}  // namespace flexloop::plant::lti
