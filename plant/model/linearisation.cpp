// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/linearisation.hpp"

#include <algorithm>

#include <unsupported/Eigen/AutoDiff>
#include "plant/model/inertia.hpp"

#include "common/input_error.hpp"
#include "plant/model/kinematics.hpp"

namespace flexloop::plant::model {

namespace {

Eigen::MatrixXd dependent_block(const Eigen::MatrixXd& J, const Partition& p) {
  Eigen::MatrixXd B(p.g_rows.size(), p.x_dependent.size());
  for (std::size_t i = 0; i < p.g_rows.size(); ++i)
    for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
      B(i, j) = J(p.g_rows[i], p.x_dependent[j]);
  return B;
}

// Solves J_gc Y_c = -RHS_g for the dependent rows (other rows of Y are zero); RHS has n_e rows,
// of which the rigid and generalised (g) rows are used.
Eigen::MatrixXd implicit_solve(const Model& m, const Partition& p,
                               const Eigen::PartialPivLU<Eigen::MatrixXd>& lu,
                               const Eigen::MatrixXd& rhs_e) {
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(m.nx(), rhs_e.cols());
  if (p.x_dependent.empty()) return Y;
  Eigen::MatrixXd rhs_g(p.g_rows.size(), rhs_e.cols());
  for (std::size_t k = 0; k < p.g_rows.size(); ++k)
    rhs_g.row(static_cast<Eigen::Index>(k)) = rhs_e.row(p.g_rows[k]);
  const Eigen::MatrixXd Yc = lu.solve(-rhs_g);
  for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
    Y.row(p.x_dependent[j]) = Yc.row(static_cast<Eigen::Index>(j));
  return Y;
}

// Inertia force of a 3-D rotational node, 4 L^T J L l'' + 8 L(l')^T J L(l) l', for AD.
template <class T>
Eigen::Matrix<T, 4, 1> euler_inertia_force(const Eigen::Matrix3d& Jb,
                                           const Eigen::Matrix<T, 4, 1>& l,
                                           const Eigen::Matrix<T, 4, 1>& ld,
                                           const Eigen::Matrix<T, 4, 1>& ldd) {
  auto Lm = [](const Eigen::Matrix<T, 4, 1>& a) {
    Eigen::Matrix<T, 3, 4> L;
    L << -a(1), a(0), a(3), -a(2), -a(2), -a(3), a(0), a(1), -a(3), a(2), -a(1), a(0);
    return L;
  };
  const Eigen::Matrix<T, 3, 3> Jt = Jb.cast<T>();
  const Eigen::Matrix<T, 3, 4> L = Lm(l);
  return T(4.0) * L.transpose() * (Jt * (L * ldd)) + T(8.0) * Lm(ld).transpose() * (Jt * (L * ld));
}

// d(g_in)/dx and d(g_in)/dx' at (x, x', x''), n_x x n_x each (translations and planar
// rotations have constant mass and no velocity terms).
void inertia_force_derivatives(const Model& m, const Eigen::VectorXd& x, const Eigen::VectorXd& xd,
                               const Eigen::VectorXd& xdd, Eigen::MatrixXd& dgdx,
                               Eigen::MatrixXd& dgdxd) {
  using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
  dgdx = Eigen::MatrixXd::Zero(m.nx(), m.nx());
  dgdxd = Eigen::MatrixXd::Zero(m.nx(), m.nx());
  if (m.dim != 3) return;
  for (const auto& n : m.nodes) {
    if (!n.rotational) continue;
    const int r = n.first_coordinate + 3;
    Eigen::Matrix<Ad, 4, 1> l, ld, ldd;
    for (int i = 0; i < 4; ++i) {
      l(i) = Ad(x(r + i), 8, i);
      ld(i) = Ad(xd(r + i), 8, 4 + i);
      ldd(i) = Ad(xdd(r + i), Eigen::VectorXd::Zero(8));
    }
    const auto g = euler_inertia_force<Ad>(n.inertia, l, ld, ldd);
    for (int i = 0; i < 4; ++i) {
      dgdx.block<1, 4>(r + i, r) = g(i).derivatives().head<4>().transpose();
      dgdxd.block<1, 4>(r + i, r) = g(i).derivatives().tail<4>().transpose();
    }
  }
}

// T = d(u)/dq of a superelement's reduced coordinates u = (interface translations, modal
// amplitudes): the interface rows of DF(x), which are constant (an interface translation is
// never a dependent coordinate), and a unit row per modal amplitude.
Eigen::MatrixXd superelement_transfer(const Model& m, const Superelement& body,
                                      const Eigen::MatrixXd& DFx) {
  const auto nb = static_cast<Eigen::Index>(body.interface_coordinates.size());
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(nb + body.mode_count(), m.nq());
  for (Eigen::Index r = 0; r < nb; ++r)
    T.row(r) = DFx.row(body.interface_coordinates[static_cast<std::size_t>(r)]);
  for (int k = 0; k < body.mode_count(); ++k) {
    const auto at = std::find(m.generalised.begin(), m.generalised.end(), body.mode_labels[k]);
    T(nb + k, at - m.generalised.begin()) = 1.0;
  }
  return T;
}

// The reduced coordinates u of a superelement at (x, q): interface displacements from the
// reference configuration, then the modal amplitudes.
Eigen::VectorXd superelement_displacement(const Model& m, const Superelement& body,
                                          const Eigen::MatrixXd& T, const Eigen::VectorXd& x,
                                          const Eigen::VectorXd& q) {
  const auto nb = static_cast<Eigen::Index>(body.interface_coordinates.size());
  Eigen::VectorXd u = T * q;  // the modal rows; the interface rows are set below
  for (Eigen::Index r = 0; r < nb; ++r) {
    const int c = body.interface_coordinates[static_cast<std::size_t>(r)];
    u(r) = x(c) - m.x_reference(c);
  }
  return u;
}

// A superelement is linear: its mass, stiffness and damping enter through T,
// Mbar += T' M_r T, Kbar += T' K_r T, Dbar += T' D_r T; nothing in Gbar, Cbar or Nbar (no
// preload, and T is constant).
void add_superelements(const Model& m, Linearisation& L) {
  for (const auto& body : m.superelements) {
    const Eigen::MatrixXd T = superelement_transfer(m, body, L.DFx);
    L.M += T.transpose() * body.M * T;
    L.K += T.transpose() * body.K * T;
    L.D += T.transpose() * body.D * T;
  }
}

bool is_zero(const Eigen::VectorXd& v) {
  return v.size() == 0 || v.isZero(0.0);
}

}  // namespace

void global_constitutive(const Model& m, Eigen::MatrixXd& S, Eigen::MatrixXd& Sd) {
  S = Eigen::MatrixXd::Zero(m.ne(), m.ne());
  Sd = Eigen::MatrixXd::Zero(m.ne(), m.ne());
  for (const auto& el : m.elements) {
    const int k = el.first_deformation, n = el.deformation_count();
    S.block(k, k, n, n) = el.stiffness;
    Sd.block(k, k, n, n) = el.damping;
  }
}

Eigen::VectorXd reference_generalised(const Model& m) {
  const Partition p = make_partition(m);
  return generalised_from_x(m, p, deformation_blocks(m), m.x_reference);
}

OperatingPoint model_operating_point(const Model& m) {
  OperatingPoint op;
  op.q = reference_generalised(m);
  op.qd = Eigen::VectorXd::Zero(m.nq());
  op.qdd = Eigen::VectorXd::Zero(m.nq());
  auto index = [&](const std::string& label) {
    return static_cast<Eigen::Index>(std::find(m.generalised.begin(), m.generalised.end(), label) -
                                     m.generalised.begin());
  };
  for (const auto& [label, v] : m.op_q) op.q(index(label)) = v;
  for (const auto& [label, v] : m.op_qd) op.qd(index(label)) = v;
  for (const auto& [label, v] : m.op_qdd) op.qdd(index(label)) = v;
  return op;
}

Linearisation linearise(const Model& m, const OperatingPoint& op) {
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  const int nq = m.nq();
  Linearisation L;
  L.q = op.q.size() ? op.q : generalised_from_x(m, p, blocks, m.x_reference);
  L.qd = op.qd.size() ? op.qd : Eigen::VectorXd::Zero(nq);
  L.qdd = op.qdd.size() ? op.qdd : Eigen::VectorXd::Zero(nq);
  L.sigma_a = op.sigma_a.size() ? op.sigma_a : Eigen::VectorXd::Zero(m.ne());
  const Eigen::VectorXd& sigma_a = L.sigma_a;
  const bool stationary = is_zero(L.qd) && is_zero(L.qdd);
  if (!stationary && !m.superelements.empty())
    throw common::InputError(m.superelements.front().source.str(),
                             "superelement '" + m.superelements.front().id +
                                 "': a model with a superelement is linearised at rest only; "
                                 "this operating point moves (qd or qdd non-zero)");
  if (!stationary)  // the beam mass's velocity terms are not formed (beam_mass.hpp)
    for (const auto& el : m.elements)
      if (el.mass_model == MassModel::kBeam)
        throw common::InputError(el.source.str(),
                                 "element '" + el.id +
                                     "': mass_model = \"beam\" is linearised at rest "
                                     "only; this operating point moves (qd or qdd "
                                     "non-zero): use lumped or consistent");

  // Kinematics: x, DF, x', x''.
  L.x = solve_configuration(m, p, blocks, L.q, m.x_reference);
  L.J = deformation_jacobian(m, blocks, L.x);
  L.DFx = geometric_transfer(m, p, L.J);
  L.DFe = L.J * L.DFx;
  // Rows known exactly from the partition: a rigid deformation is identically zero and a
  // generalised one is its own coordinate. The product above leaves round-off (~1e-17) there,
  // which stiffness 1e7 turns into spurious couplings to prescribed coordinates.
  for (int k : p.e_rigid) L.DFe.row(k).setZero();
  for (int q = 0; q < m.nq(); ++q)
    if (const int k = p.q_deformation[q]; k >= 0)
      L.DFe.row(k) = Eigen::RowVectorXd::Unit(m.nq(), q);
  L.xd = L.DFx * L.qd;
  L.xdd = L.DFx * L.qdd + convective_acceleration(m, p, blocks, L.x, L.J, L.xd);
  L.e = deformations(m, blocks, L.x);
  L.ed = L.J * L.xd;

  // Forces: constitutive stresses, then the stresses of rigid and generalised deformations from
  // the x(c) rows of the equations of reaction  J^T sigma = f - g_in.
  global_constitutive(m, L.S, L.Sd);
  L.Mx = mass_matrix(m, L.x);
  L.f = applied_forces(m);
  const Eigen::VectorXd a = inertia_forces(m, L.x, L.xd, L.xdd) - L.f;
  L.sigma = L.S * L.e + L.Sd * L.ed + sigma_a;
  for (int k = 0; k < m.ne(); ++k)  // rigid stresses are reactions, found below
    if (m.deformation_roles[k] == DeformationRole::kRigid ||
        m.deformation_roles[k] == DeformationRole::kInert)
      L.sigma(k) = 0.0;
  Eigen::VectorXd sigma_c = Eigen::VectorXd::Zero(m.ne());
  for (int k : p.e_dependent) sigma_c(k) = L.sigma(k);
  if (!p.x_dependent.empty()) {
    const Eigen::VectorXd grad = a + L.J.transpose() * sigma_c;  // gradient of psi over x
    Eigen::VectorXd grad_c(p.x_dependent.size());
    for (std::size_t j = 0; j < p.x_dependent.size(); ++j)
      grad_c(static_cast<Eigen::Index>(j)) = grad(p.x_dependent[j]);
    const Eigen::VectorXd sigma_g =
        -dependent_block(L.J, p).transpose().partialPivLu().solve(grad_c);
    for (std::size_t k = 0; k < p.g_rows.size(); ++k)
      L.sigma(p.g_rows[k]) = sigma_g(static_cast<Eigen::Index>(k));
  }

  // Mass, stiffness, damping, geometric stiffness.
  L.M = L.DFx.transpose() * L.Mx * L.DFx;
  L.K = L.DFe.transpose() * L.S * L.DFe;
  L.D = L.DFe.transpose() * L.Sd * L.DFe;
  L.G = L.DFx.transpose() * weighted_deformation_hessian(m, blocks, L.x, L.sigma) * L.DFx;
  add_superelements(m, L);

  // Velocity and acceleration terms (all zero at a stationary point).
  L.Vx = L.Wx = L.Zx = Eigen::MatrixXd::Zero(m.nx(), nq);
  L.Ved = Eigen::MatrixXd::Zero(m.ne(), nq);
  L.C = L.N = Eigen::MatrixXd::Zero(nq, nq);
  if (!stationary) {
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;
    if (!p.x_dependent.empty()) lu.compute(dependent_block(L.J, p));
    const Eigen::MatrixXd Hxd = deformation_hessian_times(m, blocks, L.x, L.xd);  // rows (H_k x')^T
    const Eigen::MatrixXd Hxdd =
        deformation_hessian_times(m, blocks, L.x, L.xdd);  // rows (H_k x'')^T
    const Eigen::MatrixXd dc_dx = deformation_curvature_gradient(m, blocks, L.x, L.xd);
    // Differentiate J_g x' = P_e q' and J_g x'' + x'^T H_g x' = P_e q'' (x(o), x(m) rows known):
    //   V = dx'/dq:    J_g V = -(H x')_g DF
    //   Z = dx''/dq':  J_g Z = -2 (H x')_g DF
    //   W = dx''/dq:   J_g W = -[(H x'')_g DF + d(x'^T H x')/dx DF + 2 (H x')_g V]
    L.Vx = implicit_solve(m, p, lu, Hxd * L.DFx);
    L.Zx = implicit_solve(m, p, lu, 2.0 * Hxd * L.DFx);
    L.Wx = implicit_solve(m, p, lu, Hxdd * L.DFx + dc_dx * L.DFx + 2.0 * Hxd * L.Vx);
    L.Ved = Hxd * L.DFx + L.J * L.Vx;  // e' = J x'
    Eigen::MatrixXd dgdx, dgdxd;
    inertia_force_derivatives(m, L.x, L.xd, L.xdd, dgdx, dgdxd);
    // R = DF^T a + DF(e)^T sigma with a = g_in(x, x', x'') - f and sigma = S e + S_d e' + sigma_a.
    L.C = L.DFx.transpose() * (L.Mx * L.Zx + dgdxd * L.DFx);
    L.N = L.DFx.transpose() * (dgdx * L.DFx + dgdxd * L.Vx + L.Mx * L.Wx) +
          L.DFe.transpose() * L.Sd * L.Ved;
  }
  return L;
}

NodalMotion nodal_motion(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         const Eigen::VectorXd& qdd) {
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  NodalMotion n;
  n.x = solve_configuration(m, p, blocks, q, m.x_reference);
  n.J = deformation_jacobian(m, blocks, n.x);
  n.DF = geometric_transfer(m, p, n.J);
  n.xd = n.DF * qd;
  n.xdd = n.DF * qdd + convective_acceleration(m, p, blocks, n.x, n.J, n.xd);
  return n;
}

Eigen::VectorXd equations_of_motion_residual(const Model& m, const Eigen::VectorXd& q,
                                             const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                             const Eigen::VectorXd& sigma_a_in) {
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  const NodalMotion n = nodal_motion(m, q, qd, qdd);
  Eigen::MatrixXd S, Sd;
  global_constitutive(m, S, Sd);
  const Eigen::VectorXd sigma_a = sigma_a_in.size() ? sigma_a_in : Eigen::VectorXd::Zero(m.ne());
  Eigen::VectorXd sigma = S * deformations(m, blocks, n.x) + Sd * (n.J * n.xd) + sigma_a;
  for (int k : p.e_rigid) sigma(k) = 0.0;  // DF(e) rows of rigid deformations vanish
  Eigen::VectorXd r = n.DF.transpose() * (inertia_forces(m, n.x, n.xd, n.xdd) - applied_forces(m)) +
                      (n.J * n.DF).transpose() * sigma;
  for (const auto& body : m.superelements) {  // T' (M_r u'' + D_r u' + K_r u), T constant
    const Eigen::MatrixXd T = superelement_transfer(m, body, n.DF);
    const Eigen::VectorXd u = superelement_displacement(m, body, T, n.x, q);
    r += T.transpose() * (body.M * (T * qdd) + body.D * (T * qd) + body.K * u);
  }
  return r;
}

}  // namespace flexloop::plant::model
