#include "plant/model/linearisation.hpp"

#include "plant/model/inertia.hpp"
#include "plant/model/input_error.hpp"
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

Linearisation linearise(const Model& m, const OperatingPoint& op) {
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  const int nq = m.nq();
  Linearisation L;
  L.q = op.q.size() ? op.q : generalised_from_x(m, p, blocks, m.x_reference);
  L.qd = op.qd.size() ? op.qd : Eigen::VectorXd::Zero(nq);
  L.qdd = op.qdd.size() ? op.qdd : Eigen::VectorXd::Zero(nq);
  const Eigen::VectorXd sigma_a = op.sigma_a.size() ? op.sigma_a : Eigen::VectorXd::Zero(m.ne());
  if (!is_zero(L.qd) || !is_zero(L.qdd))
    throw InputError(
        m.file,
        "linearisation about a moving configuration (non-zero q' or q'') is not implemented yet; "
        "linearise about a stationary configuration");

  // Kinematics: x, DF, x', x''.
  L.x = solve_configuration(m, p, blocks, L.q, m.x_reference);
  L.J = deformation_jacobian(m, blocks, L.x);
  L.DFx = geometric_transfer(m, p, L.J);
  L.DFe = L.J * L.DFx;
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

  // Velocity and acceleration dependent terms vanish at a stationary point.
  L.Vx = L.Wx = L.Zx = Eigen::MatrixXd::Zero(m.nx(), nq);
  L.Ved = Eigen::MatrixXd::Zero(m.ne(), nq);
  L.C = L.N = Eigen::MatrixXd::Zero(nq, nq);
  return L;
}

Eigen::VectorXd equations_of_motion_residual(const Model& m, const Eigen::VectorXd& q,
                                             const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                             const Eigen::VectorXd& sigma_a_in) {
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  const Eigen::VectorXd x = solve_configuration(m, p, blocks, q, m.x_reference);
  const Eigen::MatrixXd J = deformation_jacobian(m, blocks, x);
  const Eigen::MatrixXd DF = geometric_transfer(m, p, J);
  const Eigen::VectorXd xd = DF * qd;
  const Eigen::VectorXd xdd = DF * qdd + convective_acceleration(m, p, blocks, x, J, xd);
  Eigen::MatrixXd S, Sd;
  global_constitutive(m, S, Sd);
  const Eigen::VectorXd sigma_a = sigma_a_in.size() ? sigma_a_in : Eigen::VectorXd::Zero(m.ne());
  Eigen::VectorXd sigma = S * deformations(m, blocks, x) + Sd * (J * xd) + sigma_a;
  for (int k : p.e_rigid) sigma(k) = 0.0;  // DF(e) rows of rigid deformations vanish
  return DF.transpose() * (inertia_forces(m, x, xd, xdd) - applied_forces(m)) +
         (J * DF).transpose() * sigma;
}

}  // namespace flexloop::plant::model
