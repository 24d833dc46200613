// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/kinematics.hpp"

#include <unsupported/Eigen/AutoDiff>

namespace flexloop::plant::model {

namespace {

using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using AdVec = Eigen::Matrix<Ad, Eigen::Dynamic, 1>;
using Ad2 = Eigen::AutoDiffScalar<AdVec>;  // nested: second derivatives

// The deformations of one block from its local coordinates, for any scalar type.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> block_deformations(
    const Model& m, const DeformationBlock& b, const Eigen::Matrix<T, Eigen::Dynamic, 1>& xl) {
  Eigen::Matrix<T, Eigen::Dynamic, 1> e(b.count);
  if (b.element < 0) {  // Euler parameter normalisation of a 3-D rotational node
    e(0) = euler_parameter_constraint<T>(xl.template head<4>());
    return e;
  }
  const Element& el = m.elements[b.element];
  const Node& p = m.nodes[el.nodes[0]];
  const int nq0 = p.coordinate_count;  // the q node's coordinates follow the p node's
  switch (el.type) {
    case ElementType::kTruss: {
      const T zero = xl(0) - xl(0);  // a zero that carries derivative vectors of the right size
      Vec3<T> xp = Vec3<T>::Constant(zero), xq = Vec3<T>::Constant(zero);
      for (int a = 0; a < m.dim; ++a) xp(a) = xl(a), xq(a) = xl(nq0 + a);
      e(0) = truss_elongation<T>(xp, xq, el.length);
      break;
    }
    case ElementType::kPlanarBeam: {
      const Vec2<T> xp = xl.template segment<2>(0), xq = xl.template segment<2>(nq0);
      e = planar_beam_deformations<T>(xp, xl(2), xq, xl(nq0 + 2), el.planar_ref);
      break;
    }
    case ElementType::kSpatialBeam: {
      const Vec3<T> xp = xl.template segment<3>(0), xq = xl.template segment<3>(nq0);
      const Vec4<T> lp = xl.template segment<4>(3), lq = xl.template segment<4>(nq0 + 3);
      e = spatial_beam_deformations<T>(xp, lp, xq, lq, el.spatial_ref);
      break;
    }
  }
  return e;
}

Eigen::VectorXd gather(const DeformationBlock& b, const Eigen::VectorXd& x) {
  Eigen::VectorXd xl(static_cast<Eigen::Index>(b.coords.size()));
  for (std::size_t i = 0; i < b.coords.size(); ++i)
    xl(static_cast<Eigen::Index>(i)) = x(b.coords[i]);
  return xl;
}

// Local Jacobian (count x n) of a block.
Eigen::MatrixXd block_jacobian(const Model& m, const DeformationBlock& b,
                               const Eigen::VectorXd& xl) {
  const auto n = xl.size();
  AdVec xa(n);
  for (Eigen::Index i = 0; i < n; ++i) xa(i) = Ad(xl(i), n, i);
  const AdVec e = block_deformations<Ad>(m, b, xa);
  Eigen::MatrixXd J(b.count, n);
  for (int k = 0; k < b.count; ++k) {
    if (e(k).derivatives().size() == n)
      J.row(k) = e(k).derivatives().transpose();
    else
      J.row(k).setZero();  // a deformation that does not depend on x carries no derivatives
  }
  return J;
}

// Local Hessians (one n x n per deformation) of a block, by nested forward AD.
std::vector<Eigen::MatrixXd> block_hessians(const Model& m, const DeformationBlock& b,
                                            const Eigen::VectorXd& xl) {
  const auto n = xl.size();
  Eigen::Matrix<Ad2, Eigen::Dynamic, 1> xa(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    xa(i).value() = Ad(xl(i), n, i);
    xa(i).derivatives() = AdVec::Zero(n);
    for (Eigen::Index j = 0; j < n; ++j)
      xa(i).derivatives()(j) = Ad(i == j ? 1.0 : 0.0, Eigen::VectorXd::Zero(n));
  }
  const auto e = block_deformations<Ad2>(m, b, xa);
  std::vector<Eigen::MatrixXd> H(static_cast<std::size_t>(b.count), Eigen::MatrixXd::Zero(n, n));
  for (int k = 0; k < b.count; ++k) {
    const auto& d = e(k).derivatives();
    if (d.size() != n) continue;
    for (Eigen::Index i = 0; i < n; ++i)
      if (d(i).derivatives().size() == n)
        H[static_cast<std::size_t>(k)].row(i) = d(i).derivatives().transpose();
  }
  return H;
}

// Gradient over the local coordinates of v^T Hessian(D_k) v for each k: a second directional
// derivative along v (two nested one-direction levels) on a base scalar that carries the
// gradient over x, i.e. third derivatives of D contracted twice with v.
Eigen::MatrixXd block_curvature_gradient(const Model& m, const DeformationBlock& b,
                                         const Eigen::VectorXd& xl, const Eigen::VectorXd& vl) {
  using Base = Ad;
  using BaseVec = Eigen::Matrix<Base, Eigen::Dynamic, 1>;
  using L1 = Eigen::AutoDiffScalar<BaseVec>;
  using L2 = Eigen::AutoDiffScalar<Eigen::Matrix<L1, Eigen::Dynamic, 1>>;
  const auto n = xl.size();
  auto constant = [&](double v) { return Base(v, Eigen::VectorXd::Zero(n)); };
  Eigen::Matrix<L2, Eigen::Dynamic, 1> xa(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    // x_i + t1 v_i + t2 v_i: the t1 t2 coefficient of D is v^T Hess(D) v.
    const L1 value(Base(xl(i), n, i), BaseVec::Constant(1, constant(vl(i))));
    Eigen::Matrix<L1, Eigen::Dynamic, 1> der(1);
    der(0) = L1(constant(vl(i)), BaseVec::Constant(1, constant(0.0)));
    xa(i) = L2(value, der);
  }
  const auto e = block_deformations<L2>(m, b, xa);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(b.count, n);
  for (int k = 0; k < b.count; ++k) {
    const auto& d1 = e(k).derivatives();
    if (d1.size() != 1) continue;
    const auto& d2 = d1(0).derivatives();
    if (d2.size() != 1 || d2(0).derivatives().size() != n) continue;
    G.row(k) = d2(0).derivatives().transpose();
  }
  return G;
}

}  // namespace

std::vector<DeformationBlock> deformation_blocks(const Model& m) {
  std::vector<DeformationBlock> blocks;
  for (std::size_t ei = 0; ei < m.elements.size(); ++ei) {
    const Element& el = m.elements[ei];
    DeformationBlock b;
    b.element = static_cast<int>(ei);
    for (int ni : el.nodes) {
      const Node& n = m.nodes[ni];
      for (int c = 0; c < n.coordinate_count; ++c) b.coords.push_back(n.first_coordinate + c);
    }
    b.first = el.first_deformation;
    b.count = el.deformation_count();
    blocks.push_back(std::move(b));
  }
  for (std::size_t ni = 0; ni < m.nodes.size(); ++ni) {
    const Node& n = m.nodes[ni];
    if (n.euler_deformation < 0) continue;
    DeformationBlock b;
    b.node = static_cast<int>(ni);
    for (int c = 0; c < 4; ++c) b.coords.push_back(n.first_coordinate + 3 + c);
    b.first = n.euler_deformation;
    b.count = 1;
    blocks.push_back(std::move(b));
  }
  return blocks;
}

Eigen::VectorXd deformations(const Model& m, const std::vector<DeformationBlock>& blocks,
                             const Eigen::VectorXd& x) {
  Eigen::VectorXd e(m.ne());
  for (const auto& b : blocks)
    e.segment(b.first, b.count) = block_deformations<double>(m, b, gather(b, x));
  return e;
}

Eigen::MatrixXd deformation_jacobian(const Model& m, const std::vector<DeformationBlock>& blocks,
                                     const Eigen::VectorXd& x) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m.ne(), m.nx());
  for (const auto& b : blocks) {
    const Eigen::MatrixXd Jl = block_jacobian(m, b, gather(b, x));
    for (std::size_t i = 0; i < b.coords.size(); ++i)
      J.block(b.first, b.coords[i], b.count, 1) = Jl.col(static_cast<Eigen::Index>(i));
  }
  return J;
}

Eigen::MatrixXd weighted_deformation_hessian(const Model& m,
                                             const std::vector<DeformationBlock>& blocks,
                                             const Eigen::VectorXd& x, const Eigen::VectorXd& w) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m.nx(), m.nx());
  for (const auto& b : blocks) {
    if (w.segment(b.first, b.count).isZero(0.0)) continue;  // no stress, no geometric stiffness
    const auto Hl = block_hessians(m, b, gather(b, x));
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(Hl[0].rows(), Hl[0].cols());
    for (int k = 0; k < b.count; ++k) sum += w(b.first + k) * Hl[static_cast<std::size_t>(k)];
    for (std::size_t i = 0; i < b.coords.size(); ++i)
      for (std::size_t j = 0; j < b.coords.size(); ++j)
        H(b.coords[i], b.coords[j]) +=
            sum(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
  }
  return H;
}

Eigen::VectorXd deformation_curvature(const Model& m, const std::vector<DeformationBlock>& blocks,
                                      const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(m.ne());
  for (const auto& b : blocks) {
    const Eigen::VectorXd vl = gather(b, v);
    if (vl.isZero(0.0)) continue;
    const auto Hl = block_hessians(m, b, gather(b, x));
    for (int k = 0; k < b.count; ++k) c(b.first + k) = vl.dot(Hl[static_cast<std::size_t>(k)] * vl);
  }
  return c;
}

Eigen::MatrixXd deformation_hessian_times(const Model& m,
                                          const std::vector<DeformationBlock>& blocks,
                                          const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
  Eigen::MatrixXd Hv = Eigen::MatrixXd::Zero(m.ne(), m.nx());
  for (const auto& b : blocks) {
    const Eigen::VectorXd vl = gather(b, v);
    if (vl.isZero(0.0)) continue;
    const auto Hl = block_hessians(m, b, gather(b, x));
    for (int k = 0; k < b.count; ++k) {
      const Eigen::VectorXd row = Hl[static_cast<std::size_t>(k)] * vl;
      for (std::size_t i = 0; i < b.coords.size(); ++i)
        Hv(b.first + k, b.coords[i]) += row(static_cast<Eigen::Index>(i));
    }
  }
  return Hv;
}

Eigen::MatrixXd deformation_curvature_gradient(const Model& m,
                                               const std::vector<DeformationBlock>& blocks,
                                               const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(m.ne(), m.nx());
  for (const auto& b : blocks) {
    const Eigen::VectorXd vl = gather(b, v);
    if (vl.isZero(0.0)) continue;
    const Eigen::MatrixXd Gl = block_curvature_gradient(m, b, gather(b, x), vl);
    for (std::size_t i = 0; i < b.coords.size(); ++i)
      G.block(b.first, b.coords[i], b.count, 1) += Gl.col(static_cast<Eigen::Index>(i));
  }
  return G;
}

}  // namespace flexloop::plant::model
