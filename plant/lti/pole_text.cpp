// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/pole_text.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace flexloop::plant::lti {

double integrator_tolerance(const Eigen::VectorXcd& poles) {
  return poles.size() > 0 ? kIntegratorRoundOff * poles.cwiseAbs().maxCoeff() : 0.0;
}

bool is_integrator(std::complex<double> s, double tolerance) {
  return std::abs(s) <= tolerance;
}

double damping_ratio(std::complex<double> s, double tolerance) {
  if (is_integrator(s, tolerance)) return std::numeric_limits<double>::quiet_NaN();
  return -s.real() / std::abs(s);
}

std::string integrator_text(std::complex<double> s) {
  if (s == 0.0) return "integrator";
  char buf[96];
  std::snprintf(buf, sizeof buf, "integrator (computed |s| = %.2g rad/s, round-off)", std::abs(s));
  return buf;
}

std::string pole_text(std::complex<double> s, double tolerance) {
  const auto fmt = [](const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return std::string(buf);
  };
  if (is_integrator(s, tolerance)) return "0 rad/s, " + integrator_text(s);
  std::string text = fmt("%.6g", s.real());
  if (s.imag() != 0) text += (s.imag() < 0 ? " - " : " + ") + fmt("%.6g", std::abs(s.imag())) + "j";
  return text + " rad/s (" + fmt("%.6g", std::abs(s) / numeric::kTwoPi) + " Hz, damping " +
         fmt("%.4g", damping_ratio(s, tolerance)) + ")";
}

}  // namespace flexloop::plant::lti
