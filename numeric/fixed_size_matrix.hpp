// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Start-up only: turn a dynamic-size double matrix from the offline artefact into a compile-time
// sized matrix of the runtime's scalar, checking that the artefact has the compiled size.
//
//   to_fixed<Eigen::Matrix<float, 12, 12>>("DensePlant: Ad", Ad)
//
// @throws std::invalid_argument "DensePlant: Ad is 10x10, expected 12x12 (the sizes this runtime
// was compiled for)" on a size mismatch, or naming the entry when one is not finite.
// Allocates (the message); never call it inside a step.
#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>

namespace flexloop::numeric {

template <typename Fixed>
Fixed to_fixed(const std::string& what, const Eigen::MatrixXd& m) {
  static_assert(
      Fixed::RowsAtCompileTime != Eigen::Dynamic && Fixed::ColsAtCompileTime != Eigen::Dynamic,
      "the runtime works on compile-time sizes only");
  constexpr Eigen::Index kRows = Fixed::RowsAtCompileTime, kCols = Fixed::ColsAtCompileTime;
  if (m.rows() != kRows || m.cols() != kCols)
    throw std::invalid_argument(what + " is " + std::to_string(m.rows()) + "x" +
                                std::to_string(m.cols()) + ", expected " + std::to_string(kRows) +
                                "x" + std::to_string(kCols) +
                                " (the sizes this runtime was compiled for)");
  for (Eigen::Index j = 0; j < kCols; ++j)
    for (Eigen::Index i = 0; i < kRows; ++i)
      if (!std::isfinite(m(i, j)))
        throw std::invalid_argument(what + "(" + std::to_string(i) + "," + std::to_string(j) +
                                    ") is not finite");
  return m.template cast<typename Fixed::Scalar>();
}

}  // namespace flexloop::numeric
