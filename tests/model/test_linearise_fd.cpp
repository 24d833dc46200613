// SPDX-License-Identifier: BSD-3-Clause
// doc/design.md §3 validation case 4: every linearised matrix equals a finite-difference Jacobian
// of the nonlinear equations of motion R(q, q', q'') at the same configuration, stationary and
// moving (q' != 0, q'' != 0, so that Cbar and Nbar are exercised):
//   dR/dq'' = Mbar,  dR/dq' = Cbar + Dbar,  dR/dq = Kbar + Nbar + Gbar,
// and the geometric transfer function DF(x) equals the finite-difference dx/dq.
// Models (tests/model/models/) with gravity, nodal forces, dependent (redundant) elastic
// elements, rigid elements, prescribed coordinates, planar beams and spatial beams with Euler
// parameters.
#include <catch2/catch.hpp>
#include <functional>

#include "plant/model/configuration.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop::plant::model;

namespace {

// Central-difference Jacobian of f at v, step h scaled per entry.
Eigen::MatrixXd fd_jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                            const Eigen::VectorXd& v, double h) {
  const Eigen::VectorXd f0 = f(v);
  Eigen::MatrixXd J(f0.size(), v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    Eigen::VectorXd vp = v, vm = v;
    vp(i) += h;
    vm(i) -= h;
    J.col(i) = (f(vp) - f(vm)) / (2 * h);
  }
  return J;
}

double rel_err(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(1.0, b.norm());
}

void check_against_finite_differences(const Model& m, const Eigen::VectorXd& q,
                                      Eigen::VectorXd qd = {}, Eigen::VectorXd qdd = {}) {
  if (qd.size() == 0) qd = Eigen::VectorXd::Zero(m.nq());
  if (qdd.size() == 0) qdd = Eigen::VectorXd::Zero(m.nq());
  OperatingPoint op;
  op.q = q;
  op.qd = qd;
  op.qdd = qdd;
  const Linearisation L = linearise(m, op);
  const double h = 1e-6;
  // R is quadratic in q' and linear in q'': central differences are exact there for any step,
  // so a large one keeps the roundoff of the large elastic forces in R out of the comparison.
  const double h_rate = 1e-2;
  const auto dRdq = fd_jacobian(
      [&](const Eigen::VectorXd& v) { return equations_of_motion_residual(m, v, qd, qdd); }, q, h);
  const auto dRdqd = fd_jacobian(
      [&](const Eigen::VectorXd& v) { return equations_of_motion_residual(m, q, v, qdd); }, qd,
      h_rate);
  const auto dRdqdd = fd_jacobian(
      [&](const Eigen::VectorXd& v) { return equations_of_motion_residual(m, q, qd, v); }, qdd,
      h_rate);
  INFO("model " << m.name);
  CHECK(rel_err(L.K + L.N + L.G, dRdq) < 1e-6);
  CHECK(rel_err(L.C + L.D, dRdqd) < 1e-6);
  CHECK(rel_err(L.M, dRdqdd) < 1e-6);
  // The geometric stiffness alone: what stiffness and dynamic stiffness do not explain.
  CHECK(rel_err(L.G, dRdq - L.K - L.N) <
        1e-5 * std::max(1.0, L.K.norm()) / std::max(1.0, L.G.norm()) + 1e-6);

  // First-order geometric transfer function against dx/dq.
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  const auto dxdq = fd_jacobian(
      [&](const Eigen::VectorXd& v) { return solve_configuration(m, p, blocks, v, L.x); }, q, h);
  CHECK(rel_err(L.DFx, dxdq) < 1e-6);

  // Second- and third-order transfer functions used by velocity and acceleration outputs.
  const auto dxd_dq =
      fd_jacobian([&](const Eigen::VectorXd& v) { return nodal_motion(m, v, qd, qdd).xd; }, q, h);
  const auto dxdd_dq =
      fd_jacobian([&](const Eigen::VectorXd& v) { return nodal_motion(m, v, qd, qdd).xdd; }, q, h);
  const auto dxdd_dqd =
      fd_jacobian([&](const Eigen::VectorXd& v) { return nodal_motion(m, q, v, qdd).xdd; }, qd, h);
  CHECK(rel_err(L.Vx, dxd_dq) < 1e-6);
  CHECK(rel_err(L.Wx, dxdd_dq) < 1e-6);
  CHECK(rel_err(L.Zx, dxdd_dqd) < 1e-6);
  if (qd.isZero(0.0) && qdd.isZero(0.0)) {
    CHECK(L.C.isZero(0.0));
    CHECK(L.N.isZero(0.0));
  } else {
    CHECK(L.N.norm() > 1e-8 * L.K.norm());  // the moving case really exercises Nbar
  }
}

Eigen::VectorXd wave(Eigen::Index n, double a, double phase) {
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v(i) = a * std::sin(1.3 * static_cast<double>(i) + phase);
  return v;
}

}  // namespace

TEST_CASE("finite differences: planar truss mechanism at a deformed configuration") {
  const Model m = load_model("tests/model/models/truss_mechanism.toml");
  Eigen::VectorXd q = reference_generalised(m);
  q += Eigen::Vector3d(0.01, -0.02, 0.015);
  check_against_finite_differences(m, q);
}

TEST_CASE("finite differences: planar beams with a prescribed base") {
  const Model m = load_model("tests/model/models/planar_beams_on_base.toml");
  Eigen::VectorXd q = reference_generalised(m);
  q.head(5) += (Eigen::VectorXd(5) << 1e-3, 2e-3, -1e-3, 3e-3, 1e-3).finished();
  q(5) += 0.05;
  check_against_finite_differences(m, q);
}

TEST_CASE("finite differences: spatial beams with Euler parameters") {
  const Model m = load_model("tests/model/models/spatial_beams.toml");
  Eigen::VectorXd q = reference_generalised(m);
  for (int i = 0; i < q.size(); ++i) q(i) += 1e-3 * std::sin(1.7 * i + 0.3);
  check_against_finite_differences(m, q);
}

TEST_CASE("finite differences: planar truss mechanism, moving configuration") {
  const Model m = load_model("tests/model/models/truss_mechanism.toml");
  const Eigen::VectorXd q = reference_generalised(m) + Eigen::Vector3d(0.01, -0.02, 0.015);
  check_against_finite_differences(m, q, wave(3, 0.3, 0.2), wave(3, 2.0, 1.1));
}

TEST_CASE("finite differences: planar beams on a moving base, moving configuration") {
  const Model m = load_model("tests/model/models/planar_beams_on_base.toml");
  Eigen::VectorXd q = reference_generalised(m);
  q(5) += 0.05;
  check_against_finite_differences(m, q, wave(6, 0.05, 0.4), wave(6, 0.5, 2.0));
}

TEST_CASE("finite differences: spatial beams with Euler parameters, moving configuration") {
  const Model m = load_model("tests/model/models/spatial_beams.toml");
  const Eigen::VectorXd q = reference_generalised(m) + wave(12, 1e-3, 0.3);
  check_against_finite_differences(m, q, wave(12, 0.02, 0.7), wave(12, 0.3, 1.9));
}
