// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A rotation drawn uniformly: four independent normals, normalised, are a unit quaternion (Euler
// parameters, scalar first) distributed uniformly over the rotations.
#include <Eigen/Core>
#include <random>

namespace flexloop::test {

inline Eigen::Vector4d random_unit_quaternion(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)).normalized();
}

}  // namespace flexloop::test
