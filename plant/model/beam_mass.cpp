// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/beam_mass.hpp"

#include <array>
#include <cmath>

#include "plant/model/inertia.hpp"
#include "plant/model/rotation.hpp"

namespace flexloop::plant::model {

namespace {

// Four-point Gauss-Legendre on [0, 1]: exact for the degree-6 integrands here.
constexpr std::array<double, 4> kXi = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                       0.9305681557970263};
constexpr std::array<double, 4> kWeight = {0.1739274225687269, 0.3260725774312731,
                                           0.3260725774312731, 0.1739274225687269};

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// What each node's rotation does at configuration x: the beam's axis t there, its rate
// t' = T r' over the node's rotation coordinates r, and (3-D) the angular velocity w = W r' and
// the section axes.
struct NodeFrame {
  Eigen::VectorXd t;
  Eigen::MatrixXd T, W;
  Eigen::Vector3d y = Eigen::Vector3d::Zero(), z = Eigen::Vector3d::Zero();
};

NodeFrame planar_frame(const Element& el, const Node& n, bool at_p, const Eigen::VectorXd& x) {
  const PlanarBeamReference& ref = el.planar_ref;
  const double phi = x(n.first_coordinate + 2);
  const double angle = ref.beta + phi - (at_p ? ref.phi_p0 : ref.phi_q0);
  NodeFrame f;
  f.t = Eigen::Vector2d(std::cos(angle), std::sin(angle));
  f.T = Eigen::Vector2d(-std::sin(angle), std::cos(angle));
  return f;
}

NodeFrame spatial_frame(const Element& el, const Node& n, bool at_p, const Eigen::VectorXd& x) {
  const SpatialBeamReference& ref = el.spatial_ref;
  const Eigen::Vector4d lambda = x.segment<4>(n.first_coordinate + 3);
  const Eigen::Matrix3d R = rotation_matrix<double>(lambda);
  const Eigen::Vector3d y = at_p ? ref.y_p : ref.y_q, z = at_p ? ref.z_p : ref.z_q;
  NodeFrame f;
  f.y = R * y;
  f.z = R * z;
  f.t = R * y.cross(z);
  f.W = 2.0 * R * euler_l_matrix(lambda);  // global angular velocity over lambda'
  f.T = -skew(f.t) * f.W;                  // t' = w x t
  return f;
}

}  // namespace

Eigen::MatrixXd beam_element_mass(const Model& m, const Element& el, const Eigen::VectorXd& x) {
  const int dim = m.dim, nn = dim == 2 ? 3 : 7, ne = 2 * nn;
  const Node& p = m.nodes[static_cast<std::size_t>(el.nodes[0])];
  const Node& q = m.nodes[static_cast<std::size_t>(el.nodes[1])];
  const auto frame = [&](const Node& n, bool at_p) {
    return dim == 2 ? planar_frame(el, n, at_p, x) : spatial_frame(el, n, at_p, x);
  };
  const NodeFrame fp = frame(p, true), fq = frame(q, false);
  const Eigen::VectorXd c = x.segment(q.first_coordinate, dim) - x.segment(p.first_coordinate, dim);
  const double length = c.norm(), l0 = el.length;
  const Eigen::VectorXd d = c / length;
  const Eigen::MatrixXd across = Eigen::MatrixXd::Identity(dim, dim) - d * d.transpose();

  // Rows: a velocity (dim) as a linear map of the element's coordinate rates (ne).
  Eigen::MatrixXd Sp = Eigen::MatrixXd::Zero(dim, ne), Sq = Sp;  // xp', xq'
  Sp.leftCols(dim).setIdentity();
  Sq.middleCols(nn, dim).setIdentity();
  const Eigen::MatrixXd chord = Sq - Sp;          // c'
  Eigen::MatrixXd Ap = -across * chord, Aq = Ap;  // l0 t' - P c' at each end
  Ap.middleCols(dim, nn - dim) += l0 * fp.T;
  Aq.middleCols(nn + dim, nn - dim) += l0 * fq.T;
  Eigen::MatrixXd Wp, Wq;  // 3-D: the nodes' angular velocities
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  if (dim == 3) {
    Wp = Wq = Eigen::MatrixXd::Zero(3, ne);
    Wp.middleCols(3, 4) = fp.W;
    Wq.middleCols(nn + 3, 4) = fq.W;
    Eigen::Vector3d ey = (across * (fp.y + fq.y)).normalized();
    const Eigen::Vector3d ez = Eigen::Vector3d(d).cross(ey);
    J = el.rho_Iy * ey * ey.transpose() + el.rho_Iz * ez * ez.transpose();
  }

  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(ne, ne);
  for (std::size_t g = 0; g < kXi.size(); ++g) {
    const double s = kXi[g], w = kWeight[g];
    const double h2 = s * (1 - s) * (1 - s), h4 = -s * s * (1 - s);
    const double dh2 = 1 - 4 * s + 3 * s * s, dh4 = -2 * s + 3 * s * s;
    const Eigen::MatrixXd v = (1 - s) * Sp + s * Sq + h2 * Ap + h4 * Aq;
    const Eigen::MatrixXd v_xi = chord + dh2 * Ap + dh4 * Aq;
    M.noalias() += (el.mass * w) * v.transpose() * v;
    if (dim == 2) {  // bending rate about the plane's normal: (d x v_xi)_z / |c|
      const Eigen::RowVectorXd wb = (d(0) * v_xi.row(1) - d(1) * v_xi.row(0)) / length;
      M.noalias() += (el.rho_Iz * l0 * w) * wb.transpose() * wb;
    } else {
      const Eigen::MatrixXd wb = skew(d) * v_xi / length;
      const Eigen::RowVectorXd wt = d.transpose() * ((1 - s) * Wp + s * Wq);
      M.noalias() += (l0 * w) * wb.transpose() * J * wb;
      M.noalias() += ((el.rho_Iy + el.rho_Iz) * l0 * w) * wt.transpose() * wt;
    }
  }
  return M;
}

}  // namespace flexloop::plant::model
