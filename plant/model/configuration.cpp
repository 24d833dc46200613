// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/configuration.hpp"

#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"

namespace flexloop::plant::model {

namespace {

Eigen::MatrixXd select(const Eigen::MatrixXd& A, const std::vector<int>& rows,
                       const std::vector<int>& cols) {
  // Column-major on both sides: the inner loop runs down a column (a strided row-wise walk of
  // a large A costs a cache miss per entry).
  Eigen::MatrixXd S(rows.size(), cols.size());
  for (std::size_t j = 0; j < cols.size(); ++j) {
    const auto a = A.col(cols[j]);
    for (std::size_t i = 0; i < rows.size(); ++i)
      S(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = a(rows[i]);
  }
  return S;
}

// Right-hand side of the generalised rows of G: [0; e_m(q)].
Eigen::VectorXd g_target(const Partition& p, const Eigen::VectorXd& q) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(p.g_rows.size()));
  for (std::size_t i = 0; i < p.q_deformation.size(); ++i) {
    if (p.q_deformation[i] < 0) continue;
    for (std::size_t k = 0; k < p.g_rows.size(); ++k)
      if (p.g_rows[k] == p.q_deformation[i])
        r(static_cast<Eigen::Index>(k)) = q(static_cast<Eigen::Index>(i));
  }
  return r;
}

[[noreturn]] void report_singular(const Model& m, const Partition& p, const Eigen::MatrixXd& Jc) {
  // Undetermined coordinates: columns outside the rank-revealing QR's leading pivots.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Jc);
  qr.setThreshold(1e-10);
  const auto rank = qr.rank();
  std::ostringstream os;
  os << "kinematic Jacobian of the rigid and generalised deformations with respect to the "
        "dependent coordinates is "
        "singular (rank "
     << rank << " of " << Jc.rows() << "): ";
  os << "coordinates not determined: ";
  for (Eigen::Index i = rank; i < Jc.cols(); ++i)
    os << (i > rank ? ", " : "")
       << m.coordinate_labels[p.x_dependent[qr.colsPermutation().indices()(i)]];
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qrt(Jc.transpose());
  qrt.setThreshold(1e-10);
  os << "; redundant deformations: ";
  for (Eigen::Index i = rank; i < Jc.rows(); ++i)
    os << (i > rank ? ", " : "")
       << m.deformation_labels[p.g_rows[qrt.colsPermutation().indices()(i)]];
  os << " (fix or free those coordinates, or release those deformations)";
  throw common::InputError(m.file, os.str());
}

}  // namespace

Partition make_partition(const Model& m) {
  Partition p;
  for (int i = 0; i < m.nx(); ++i) {
    switch (m.coordinate_roles[i]) {
      case CoordinateRole::kFixed:
        p.x_fixed.push_back(i);
        break;
      case CoordinateRole::kDependent:
        p.x_dependent.push_back(i);
        break;
      default:
        p.x_generalised.push_back(i);
        break;
    }
  }
  for (int k = 0; k < m.ne(); ++k) {
    switch (m.deformation_roles[k]) {
      case DeformationRole::kRigid:
        p.e_rigid.push_back(k);
        break;
      case DeformationRole::kDependent:
        p.e_dependent.push_back(k);
        break;
      case DeformationRole::kInert:
        break;
      default:
        p.e_generalised.push_back(k);
        break;
    }
  }
  p.g_rows = p.e_rigid;
  p.g_rows.insert(p.g_rows.end(), p.e_generalised.begin(), p.e_generalised.end());
  for (const auto& label : m.generalised) {
    p.q_coordinate.push_back(m.coordinate_index(label));
    p.q_deformation.push_back(m.deformation_index(label));
  }
  return p;
}

Eigen::VectorXd generalised_from_x(const Model& m, const Partition& p,
                                   const std::vector<DeformationBlock>& blocks,
                                   const Eigen::VectorXd& x) {
  const Eigen::VectorXd e = deformations(m, blocks, x);
  Eigen::VectorXd q(m.nq());
  for (int i = 0; i < m.nq(); ++i)  // a superelement's modal amplitude: zero in x's reference
    q(i) = p.q_coordinate[i] >= 0    ? x(p.q_coordinate[i])
           : p.q_deformation[i] >= 0 ? e(p.q_deformation[i])
                                     : 0.0;
  return q;
}

Eigen::VectorXd solve_configuration(const Model& m, const Partition& p,
                                    const std::vector<DeformationBlock>& blocks,
                                    const Eigen::VectorXd& q, const Eigen::VectorXd& guess) {
  Eigen::VectorXd x = guess;
  for (int i = 0; i < m.nq(); ++i)
    if (p.q_coordinate[i] >= 0) x(p.q_coordinate[i]) = q(i);
  const Eigen::VectorXd target = g_target(p, q);
  const double scale = 1.0 + x.cwiseAbs().maxCoeff();
  for (int iter = 0; iter < 50; ++iter) {
    const Eigen::VectorXd e = deformations(m, blocks, x);
    Eigen::VectorXd r(static_cast<Eigen::Index>(p.g_rows.size()));
    for (std::size_t k = 0; k < p.g_rows.size(); ++k)
      r(static_cast<Eigen::Index>(k)) = e(p.g_rows[k]);
    r -= target;
    if (p.x_dependent.empty()) return x;
    const Eigen::MatrixXd Jc = select(deformation_jacobian(m, blocks, x), p.g_rows, p.x_dependent);
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(Jc);
    if (!(lu.rcond() > 1e-13)) report_singular(m, p, Jc);
    const Eigen::VectorXd dx = lu.solve(r);
    for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
      x(p.x_dependent[j]) -= dx(static_cast<Eigen::Index>(j));
    if (dx.cwiseAbs().maxCoeff() <= 1e-15 * scale && r.cwiseAbs().maxCoeff() <= 1e-13 * scale)
      return x;
    if (iter > 2 && dx.cwiseAbs().maxCoeff() <= 1e-14 * scale) return x;
  }
  throw std::runtime_error(m.file +
                           ": kinematic Newton iteration did not converge (configuration beyond "
                           "the mechanism's reach?)");
}

Eigen::MatrixXd geometric_transfer(const Model& m, const Partition& p, const Eigen::MatrixXd& J) {
  const auto nq = m.nq();
  Eigen::MatrixXd DF = Eigen::MatrixXd::Zero(m.nx(), nq);
  // rhs = P_e - J_gm P_x  (columns per q)
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(p.g_rows.size()), nq);
  for (int i = 0; i < nq; ++i) {
    if (p.q_coordinate[i] >= 0) {
      DF(p.q_coordinate[i], i) = 1.0;
      for (std::size_t k = 0; k < p.g_rows.size(); ++k)
        rhs(static_cast<Eigen::Index>(k), i) = -J(p.g_rows[k], p.q_coordinate[i]);
    } else {
      for (std::size_t k = 0; k < p.g_rows.size(); ++k)
        if (p.g_rows[k] == p.q_deformation[i]) rhs(static_cast<Eigen::Index>(k), i) = 1.0;
    }
  }
  if (p.x_dependent.empty()) return DF;
  const Eigen::MatrixXd Jc = select(J, p.g_rows, p.x_dependent);
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(Jc);
  if (!(lu.rcond() > 1e-13)) report_singular(m, p, Jc);
  const Eigen::MatrixXd dxc = lu.solve(rhs);
  for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
    DF.row(p.x_dependent[j]) = dxc.row(static_cast<Eigen::Index>(j));
  return DF;
}

Eigen::VectorXd convective_acceleration(const Model& m, const Partition& p,
                                        const std::vector<DeformationBlock>& blocks,
                                        const Eigen::VectorXd& x, const Eigen::MatrixXd& J,
                                        const Eigen::VectorXd& xdot) {
  // Differentiating G(x) = r(q) twice with q'' = 0: J_gc xdd_c = -(xdot^T Hess(G) xdot).
  Eigen::VectorXd xdd = Eigen::VectorXd::Zero(m.nx());
  if (p.x_dependent.empty()) return xdd;
  const Eigen::VectorXd curv = deformation_curvature(m, blocks, x, xdot);
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(p.g_rows.size()));
  for (std::size_t k = 0; k < p.g_rows.size(); ++k)
    rhs(static_cast<Eigen::Index>(k)) = -curv(p.g_rows[k]);
  const Eigen::VectorXd xc = select(J, p.g_rows, p.x_dependent).partialPivLu().solve(rhs);
  for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
    xdd(p.x_dependent[j]) = xc(static_cast<Eigen::Index>(j));
  return xdd;
}

}  // namespace flexloop::plant::model
