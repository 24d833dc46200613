// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/inertia.hpp"

#include "plant/model/beam_mass.hpp"
#include "plant/model/element_properties.hpp"

namespace flexloop::plant::model {

Eigen::Matrix<double, 3, 4> euler_l_matrix(const Eigen::Vector4d& l) {
  Eigen::Matrix<double, 3, 4> L;
  L << -l(1), l(0), l(3), -l(2),  //
      -l(2), -l(3), l(0), l(1),   //
      -l(3), l(2), -l(1), l(0);
  return L;
}

namespace {

// Adds an element's mass matrix, over (node p's coordinates, node q's coordinates) in two equal
// halves, to the model's.
void add_element_mass(Eigen::MatrixXd& M, const Model& m, const Element& el,
                      const Eigen::MatrixXd& Me) {
  const Eigen::Index n = Me.rows() / 2;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      M.block(m.nodes[el.nodes[i]].first_coordinate, m.nodes[el.nodes[j]].first_coordinate, n, n) +=
          Me.block(i * n, j * n, n, n);
}

// Translational mass matrix (constant): nodes and elements.
Eigen::MatrixXd translational_mass(const Model& m) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m.nx(), m.nx());
  for (const auto& n : m.nodes)
    for (int a = 0; a < m.dim; ++a) M(n.first_coordinate + a, n.first_coordinate + a) += n.mass;
  for (const auto& el : m.elements) {
    if (el.mass == 0.0 || el.mass_model == MassModel::kBeam) continue;  // mass_matrix() adds it
    add_element_mass(
        M, m, el,
        element_translational_mass(el.mass, m.dim, el.mass_model == MassModel::kConsistent));
  }
  return M;
}

}  // namespace

Eigen::MatrixXd mass_matrix(const Model& m, const Eigen::VectorXd& x) {
  Eigen::MatrixXd M = translational_mass(m);
  for (const auto& n : m.nodes) {
    if (!n.rotational) continue;
    const int r = n.first_coordinate + m.dim;
    if (m.dim == 2) {
      M(r, r) += n.inertia(2, 2);
    } else {
      const auto L = euler_l_matrix(x.segment<4>(r));
      M.block<4, 4>(r, r) += 4.0 * L.transpose() * n.inertia * L;
    }
  }
  for (const auto& el : m.elements) {
    if (el.mass_model == MassModel::kBeam) add_element_mass(M, m, el, beam_element_mass(m, el, x));
  }
  return M;
}

Eigen::VectorXd applied_forces(const Model& m) {
  Eigen::VectorXd g_rep = Eigen::VectorXd::Zero(m.nx());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(m.nx());
  for (const auto& n : m.nodes) {
    g_rep.segment(n.first_coordinate, m.dim) = m.gravity;
    f.segment(n.first_coordinate, m.dim) = n.force;
  }
  f += translational_mass(m) * g_rep;
  for (const auto& el : m.elements)  // a beam's weight: half at each end (no end moments)
    if (el.mass_model == MassModel::kBeam)
      for (int end : el.nodes)
        f.segment(m.nodes[end].first_coordinate, m.dim) += el.mass / 2 * m.gravity;
  return f;
}

Eigen::VectorXd inertia_forces(const Model& m, const Eigen::VectorXd& x, const Eigen::VectorXd& xd,
                               const Eigen::VectorXd& xdd) {
  Eigen::VectorXd g = mass_matrix(m, x) * xdd;
  if (m.dim == 3) {
    for (const auto& n : m.nodes) {
      if (!n.rotational) continue;
      const int r = n.first_coordinate + 3;
      const Eigen::Vector4d ld = xd.segment<4>(r);
      g.segment<4>(r) +=
          8.0 * euler_l_matrix(ld).transpose() * n.inertia * euler_l_matrix(x.segment<4>(r)) * ld;
    }
  }
  return g;
}

}  // namespace flexloop::plant::model
