// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/superelement_residual.hpp"

#include <cmath>
#include <limits>

namespace flexloop::plant::model {

ResidualStiffness residual_stiffness(const Superelement& body, std::complex<double> a,
                                     std::complex<double> b) {
  ResidualStiffness out;
  const auto& nu = body.residual_moments;
  if (nu.empty() || !(body.residual_cut_off_rad2 > 0)) return out;
  const std::complex<double> z = b / (a * body.residual_cut_off_rad2);
  out.ratio = std::abs(z);
  const auto terms = static_cast<double>(nu.size());
  out.remainder = out.ratio < 1 ? std::pow(out.ratio, terms) / (1 - out.ratio)
                                : std::numeric_limits<double>::infinity();
  // Horner in z: sum_j z^j nu_j.
  Eigen::MatrixXcd sum = nu.back().cast<std::complex<double>>();
  for (std::size_t j = nu.size() - 1; j-- > 0;)
    sum = (z * sum).eval() + nu[j].cast<std::complex<double>>();
  out.delta = -(b * b / a) * sum;
  return out;
}

}  // namespace flexloop::plant::model
