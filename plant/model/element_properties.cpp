// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/element_properties.hpp"

#include <stdexcept>

namespace flexloop::plant::model {

namespace {

void require_length(double l0) {
  if (!(l0 > 0.0)) throw std::invalid_argument("beam stiffness: element length must be positive");
}

// (EI/l0^3) [4 -2; -2 4]: the bending block for the unscaled SPACAR deformations.
Eigen::Matrix2d bending_block(double EI, double l0) {
  Eigen::Matrix2d b;
  b << 4.0, -2.0, -2.0, 4.0;
  return (EI / (l0 * l0 * l0)) * b;
}

}  // namespace

Eigen::Matrix<double, 6, 6> spatial_beam_stiffness(const BeamSection& s, double l0) {
  require_length(l0);
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Zero();
  S(0, 0) = s.E * s.A / l0;
  S(1, 1) = s.G * s.J / (l0 * l0 * l0);
  S.block<2, 2>(2, 2) = bending_block(s.E * s.Iy, l0);
  S.block<2, 2>(4, 4) = bending_block(s.E * s.Iz, l0);
  return S;
}

Eigen::Matrix3d planar_beam_stiffness(double E, double A, double I, double l0) {
  require_length(l0);
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  S(0, 0) = E * A / l0;
  S.block<2, 2>(1, 1) = bending_block(E * I, l0);
  return S;
}

Eigen::MatrixXd element_translational_mass(double mass, int dim, bool consistent) {
  if (dim != 2 && dim != 3) throw std::invalid_argument("element mass: dim must be 2 or 3");
  if (!(mass >= 0.0)) throw std::invalid_argument("element mass: mass must not be negative");
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(dim, dim);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * dim, 2 * dim);
  if (consistent) {
    M.topLeftCorner(dim, dim) = (mass / 3.0) * I;
    M.bottomRightCorner(dim, dim) = (mass / 3.0) * I;
    M.topRightCorner(dim, dim) = (mass / 6.0) * I;
    M.bottomLeftCorner(dim, dim) = (mass / 6.0) * I;
  } else {
    M.topLeftCorner(dim, dim) = (mass / 2.0) * I;
    M.bottomRightCorner(dim, dim) = (mass / 2.0) * I;
  }
  return M;
}

}  // namespace flexloop::plant::model
