// DESIGN.md §3 validation case 4: every linearised matrix equals a finite-difference Jacobian of
// the nonlinear equations of motion R(q, q', q'') at the same configuration, stationary and
// moving (q' != 0, q'' != 0, so that Cbar and Nbar are exercised):
//   dR/dq'' = Mbar,  dR/dq' = Cbar + Dbar,  dR/dq = Kbar + Nbar + Gbar,
// and the geometric transfer function DF(x) equals the finite-difference dx/dq.
// Models with gravity, nodal forces, dependent (redundant) elastic elements, rigid elements,
// prescribed coordinates, planar beams and spatial beams with Euler parameters.
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

// Nodal velocities and accelerations from (q, q', q''), by the kinematic solution alone.
struct Motion {
  Eigen::VectorXd xd, xdd;
};
Motion nodal_motion(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                    const Eigen::VectorXd& qdd) {
  const Partition p = make_partition(m);
  const auto blocks = deformation_blocks(m);
  const Eigen::VectorXd x = solve_configuration(m, p, blocks, q, m.x_reference);
  const Eigen::MatrixXd J = deformation_jacobian(m, blocks, x);
  const Eigen::MatrixXd DF = geometric_transfer(m, p, J);
  Motion mo{DF * qd, {}};
  mo.xdd = DF * qdd + convective_acceleration(m, p, blocks, x, J, mo.xd);
  return mo;
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

const char* kTrussMechanism = R"(
[model]
name = "planar truss with gravity, rigid link, redundant spring, nodal force"
dimension = 2
gravity = [0.0, -9.81]
[[node]]
id = "1"
position = [0.0, 0.0]
[[node]]
id = "2"
position = [1.0, 0.6]
mass = 3.0
force = [40.0, -25.0]
[[node]]
id = "3"
position = [2.2, 0.0]
[[node]]
id = "4"
position = [1.3, -0.7]
mass = 1.5
[[element]]
id = "a"
type = "truss"
nodes = ["1", "2"]
stiffness = 2.0e4
damping = 3.0
[[element]]
id = "b"
type = "truss"
nodes = ["2", "3"]
stiffness = 1.5e4
damping = 2.0
mass = 0.4
mass_model = "consistent"
[[element]]
id = "c"
type = "truss"
nodes = ["2", "4"]
mode = "rigid"
[[element]]
id = "d"
type = "truss"
nodes = ["3", "4"]
stiffness = 9.0e3
damping = 1.0
[[element]]
id = "e"
type = "truss"
nodes = ["1", "4"]
stiffness = 5.0e3
damping = 0.5
[coordinates]
fixed_nodes = ["1", "3"]
dynamic = ["e1.a", "e1.b", "e1.d"]
)";

const char* kPlanarBeams = R"(
[model]
name = "planar beam cantilever on a prescribed base, tip force and gravity"
dimension = 2
gravity = [0.0, -9.81]
[[node]]
id = "0"
position = [0.0, 0.0]
rotational = true
[[node]]
id = "1"
position = [0.5, 0.1]
rotational = true
mass = 0.8
inertia = 0.01
[[node]]
id = "2"
position = [1.0, 0.15]
rotational = true
mass = 0.5
inertia = 0.005
force = [-30.0, 12.0]
[[element]]
id = "b1"
type = "planar_beam"
nodes = ["0", "1"]
E = 7.0e10
A = 2.0e-4
I = 1.0e-9
rho = 2700.0
damping = [0.1, 0.01, 0.01]
[[element]]
id = "b2"
type = "planar_beam"
nodes = ["1", "2"]
E = 7.0e10
A = 2.0e-4
I = 1.0e-9
rho = 2700.0
modes = ["rigid", "flexible", "flexible"]
[coordinates]
fixed = ["y.0", "phi.0"]
dynamic = ["e1.b1", "e2.b1", "e3.b1", "e2.b2", "e3.b2"]
prescribed = ["x.0"]
)";

const char* kSpatialBeams = R"(
[model]
name = "spatial beam cantilever with Euler parameters, gravity and tip force"
dimension = 3
gravity = [0.0, 0.0, -9.81]
[[node]]
id = "0"
position = [0.0, 0.0, 0.0]
rotational = true
[[node]]
id = "1"
position = [0.4, 0.1, 0.05]
rotational = true
mass = 1.2
inertia = [0.02, 0.03, 0.04]
[[node]]
id = "2"
position = [0.8, 0.15, 0.2]
rotational = true
orientation = [0.9238795325112867, 0.0, 0.0, 0.3826834323650898]
mass = 0.7
inertia = [0.01, 0.012, 0.015, 0.001, 0.0, 0.002]
force = [5.0, -20.0, 10.0]
[[element]]
id = "s1"
type = "beam"
nodes = ["0", "1"]
E = 2.1e11
G = 8.0e10
A = 1.0e-4
Iy = 8.0e-10
Iz = 1.2e-9
J = 1.5e-9
rho = 7800.0
damping = [1.0, 0.1, 0.1, 0.1, 0.1, 0.1]
[[element]]
id = "s2"
type = "beam"
nodes = ["1", "2"]
E = 2.1e11
G = 8.0e10
A = 1.0e-4
Iy = 8.0e-10
Iz = 1.2e-9
J = 1.5e-9
y_axis = [0.0, 0.0, 1.0]
[coordinates]
fixed_nodes = ["0"]
dynamic = ["e1.s1", "e2.s1", "e3.s1", "e4.s1", "e5.s1", "e6.s1", "e1.s2", "e2.s2", "e3.s2", "e4.s2", "e5.s2", "e6.s2"]
)";

}  // namespace

TEST_CASE("finite differences: planar truss mechanism at a deformed configuration") {
  const Model m = parse_model(kTrussMechanism, "truss.toml");
  Eigen::VectorXd q = reference_generalised(m);
  q += Eigen::Vector3d(0.01, -0.02, 0.015);
  check_against_finite_differences(m, q);
}

TEST_CASE("finite differences: planar beams with a prescribed base") {
  const Model m = parse_model(kPlanarBeams, "beams2d.toml");
  Eigen::VectorXd q = reference_generalised(m);
  q.head(5) += (Eigen::VectorXd(5) << 1e-3, 2e-3, -1e-3, 3e-3, 1e-3).finished();
  q(5) += 0.05;
  check_against_finite_differences(m, q);
}

TEST_CASE("finite differences: spatial beams with Euler parameters") {
  const Model m = parse_model(kSpatialBeams, "beams3d.toml");
  Eigen::VectorXd q = reference_generalised(m);
  for (int i = 0; i < q.size(); ++i) q(i) += 1e-3 * std::sin(1.7 * i + 0.3);
  check_against_finite_differences(m, q);
}

TEST_CASE("finite differences: planar truss mechanism, moving configuration") {
  const Model m = parse_model(kTrussMechanism, "truss.toml");
  const Eigen::VectorXd q = reference_generalised(m) + Eigen::Vector3d(0.01, -0.02, 0.015);
  check_against_finite_differences(m, q, wave(3, 0.3, 0.2), wave(3, 2.0, 1.1));
}

TEST_CASE("finite differences: planar beams on a moving base, moving configuration") {
  const Model m = parse_model(kPlanarBeams, "beams2d.toml");
  Eigen::VectorXd q = reference_generalised(m);
  q(5) += 0.05;
  check_against_finite_differences(m, q, wave(6, 0.05, 0.4), wave(6, 0.5, 2.0));
}

TEST_CASE("finite differences: spatial beams with Euler parameters, moving configuration") {
  const Model m = parse_model(kSpatialBeams, "beams3d.toml");
  const Eigen::VectorXd q = reference_generalised(m) + wave(12, 1e-3, 0.3);
  check_against_finite_differences(m, q, wave(12, 0.02, 0.7), wave(12, 0.3, 1.9));
}
