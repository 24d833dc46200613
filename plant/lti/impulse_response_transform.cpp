// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/impulse_response_transform.hpp"

#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>

#include "numeric/constants.hpp"

namespace flexloop::plant::lti {

namespace {

// frac(a k) in [0, 1) with the product's rounding error added back (a k is exact up to it).
double turns(double a, long k) {
  const double kd = static_cast<double>(k);
  const double p = a * kd;
  const double error = std::fma(a, kd, -p);
  const double t = (p - std::floor(p)) + error;
  return t - std::floor(t);
}

}  // namespace

ImpulseResponseTransform::ImpulseResponseTransform(std::vector<double> frequencies_hz, double dt,
                                                   Eigen::Index outputs, Eigen::Index inputs)
    : outputs_(outputs) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw std::invalid_argument("ImpulseResponseTransform: the sample time must be > 0");
  if (outputs < 1 || inputs < 1)
    throw std::invalid_argument("ImpulseResponseTransform: needs an output and an input");
  for (double f : frequencies_hz) {
    if (!std::isfinite(f))
      throw std::invalid_argument("ImpulseResponseTransform: a frequency is not finite");
    cycles_per_sample_.push_back(f * dt);
  }
  const auto n = static_cast<Eigen::Index>(cycles_per_sample_.size());
  real_.assign(static_cast<std::size_t>(inputs), Eigen::MatrixXd::Zero(outputs, n));
  imaginary_ = real_;
}

void ImpulseResponseTransform::check(Eigen::Index input, long k0, Eigen::Index rows) const {
  if (input < 0 || input >= static_cast<Eigen::Index>(real_.size()))
    throw std::invalid_argument("ImpulseResponseTransform: input " + std::to_string(input) +
                                " out of range");
  if (rows != outputs_ || k0 < 0)
    throw std::invalid_argument("ImpulseResponseTransform: " + std::to_string(rows) + " rows for " +
                                std::to_string(outputs_) + " outputs, or a negative first sample");
}

void ImpulseResponseTransform::add(Eigen::Index input, long k0,
                                   const Eigen::Ref<const Eigen::MatrixXd>& h) {
  check(input, k0, h.rows());
  const Eigen::Index samples = h.cols(), n = static_cast<Eigen::Index>(cycles_per_sample_.size());
  cos_.resize(samples, n);
  sin_.resize(samples, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double a = cycles_per_sample_[static_cast<std::size_t>(i)];
    std::complex<double> p = std::polar(1.0, -numeric::kTwoPi * turns(a, k0));
    const std::complex<double> r = std::polar(1.0, -numeric::kTwoPi * turns(a, 1));
    for (Eigen::Index k = 0; k < samples; ++k, p *= r) {
      cos_(k, i) = p.real();
      sin_(k, i) = p.imag();
    }
  }
  const auto j = static_cast<std::size_t>(input);
  real_[j].noalias() += h * cos_;
  imaginary_[j].noalias() += h * sin_;
}

void ImpulseResponseTransform::add_constant_tail(Eigen::Index input, long k0,
                                                 const Eigen::Ref<const Eigen::VectorXd>& value) {
  check(input, k0, value.size());
  const auto j = static_cast<std::size_t>(input);
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(cycles_per_sample_.size()); ++i) {
    const double a = cycles_per_sample_[static_cast<std::size_t>(i)];
    const double one_turn = turns(a, 1);
    for (Eigen::Index r = 0; r < outputs_; ++r) {
      if (value(r) == 0) continue;
      if (one_turn == 0) {  // z = 1: the sum of a constant does not converge
        real_[j](r, i) = value(r) * std::numeric_limits<double>::infinity();
        continue;
      }
      const std::complex<double> t = value(r) * std::polar(1.0, -numeric::kTwoPi * turns(a, k0)) /
                                     (1.0 - std::polar(1.0, -numeric::kTwoPi * one_turn));
      real_[j](r, i) += t.real();
      imaginary_[j](r, i) += t.imag();
    }
  }
}

std::vector<Eigen::MatrixXcd> ImpulseResponseTransform::response() const {
  const auto inputs = static_cast<Eigen::Index>(real_.size());
  std::vector<Eigen::MatrixXcd> r;
  r.reserve(cycles_per_sample_.size());
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(cycles_per_sample_.size()); ++i) {
    Eigen::MatrixXcd m(outputs_, inputs);
    for (Eigen::Index j = 0; j < inputs; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      m.col(j).real() = real_[jj].col(i);
      m.col(j).imag() = imaginary_[jj].col(i);
    }
    r.push_back(std::move(m));
  }
  return r;
}

}  // namespace flexloop::plant::lti
