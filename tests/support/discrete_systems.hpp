// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Discrete test plants with known eigenvalues: Ad = S Λ S^-1 with Λ real block-diagonal (a 2x2
// block r [[cos θ, sin θ], [-sin θ, cos θ]] per complex pair r e^{±jθ}, a 1x1 block per real
// pole) and S a random, well-conditioned basis (I + 0.3 R, R uniform in [-1, 1]); Bd, Cd, Dd
// uniform random (test::random_matrix). Seeded, so every run builds the same plant.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "plant/lti/discretise.hpp"
#include "tests/discretise/reference.hpp"  // random_matrix, numbered

namespace flexloop::test {

struct DiscretePole {
  double radius, angle_rad;  ///< angle 0: a real pole at z = radius (one state)
};

inline plant::lti::DiscreteStateSpace discrete_system(const std::vector<DiscretePole>& poles,
                                                      Eigen::Index nu, Eigen::Index ny,
                                                      unsigned seed, double dt = 1e-4) {
  Eigen::Index n = 0;
  for (const auto& p : poles) n += p.angle_rad == 0 ? 1 : 2;
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  Eigen::Index i = 0;
  for (const auto& p : poles) {
    if (p.angle_rad == 0) {
      L(i, i) = p.radius;
      i += 1;
      continue;
    }
    const double c = p.radius * std::cos(p.angle_rad), s = p.radius * std::sin(p.angle_rad);
    L.block<2, 2>(i, i) << c, s, -s, c;
    i += 2;
  }
  std::mt19937 rng(seed);
  const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(n, n) + 0.3 * random_matrix(rng, n, n);
  plant::lti::DiscreteStateSpace d{};
  d.sys.A = S * L * S.inverse();
  d.sys.B = random_matrix(rng, n, nu);
  d.sys.C = random_matrix(rng, ny, n);
  d.sys.D = random_matrix(rng, ny, nu);
  d.sys.states = numbered("x", n);
  d.sys.inputs = numbered("u", nu);
  d.sys.outputs = numbered("y", ny);
  d.dt = dt;
  d.method = plant::lti::DiscretisationMethod::kZeroOrderHold;
  d.spectral_radius = plant::lti::spectral_radius(d.sys.A);
  return d;
}

}  // namespace flexloop::test
