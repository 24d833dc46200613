// SPDX-License-Identifier: BSD-3-Clause
// Element deformations: zero in the undeformed state, invariant under rigid motions (finite
// rotations up to pi, deformed configurations), AutoDiff derivatives (1st, nested 2nd and 3rd)
// against central finite differences, and the input checks of the reference builders.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>
#include <type_traits>

#include "plant/model/element_kinematics.hpp"
#include "tests/support/random_rotation.hpp"

#include <unsupported/Eigen/AutoDiff>

using namespace flexloop::plant::model;

namespace {

using VecX = Eigen::VectorXd;
using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using Ad2 = Eigen::AutoDiffScalar<Eigen::Matrix<Ad, Eigen::Dynamic, 1>>;
using Ad3 = Eigen::AutoDiffScalar<Eigen::Matrix<Ad2, Eigen::Dynamic, 1>>;

Eigen::Vector3d randn3(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return {n(rng), n(rng), n(rng)};
}

// Rigid motion of a node's Euler parameters, by Eigen's quaternion product (not the code under
// test).
Eigen::Vector4d rotate_lambda(const Eigen::Vector4d& g, const Eigen::Vector4d& l) {
  const Eigen::Quaterniond r =
      Eigen::Quaterniond(g(0), g(1), g(2), g(3)) * Eigen::Quaterniond(l(0), l(1), l(2), l(3));
  return {r.w(), r.x(), r.y(), r.z()};
}

// Element functions on a flat coordinate vector, for any scalar.
// spatial: (xp, lambda_p, xq, lambda_q) = 14; planar: (xp, phi_p, xq, phi_q) = 6; truss: 6.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> spatial_fn(const Eigen::Matrix<T, Eigen::Dynamic, 1>& x,
                                               const SpatialBeamReference& ref) {
  const Vec3<T> xp = x.template segment<3>(0), xq = x.template segment<3>(7);
  const Vec4<T> lp = x.template segment<4>(3), lq = x.template segment<4>(10);
  return spatial_beam_deformations<T>(xp, lp, xq, lq, ref);
}
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> planar_fn(const Eigen::Matrix<T, Eigen::Dynamic, 1>& x,
                                              const PlanarBeamReference& ref) {
  const Vec2<T> xp = x.template segment<2>(0), xq = x.template segment<2>(3);
  return planar_beam_deformations<T>(xp, x(2), xq, x(5), ref);
}
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> truss_fn(const Eigen::Matrix<T, Eigen::Dynamic, 1>& x,
                                             double l0) {
  Eigen::Matrix<T, Eigen::Dynamic, 1> e(1);
  const Vec3<T> xp = x.template segment<3>(0), xq = x.template segment<3>(3);
  e(0) = truss_elongation<T>(xp, xq, l0);
  return e;
}
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> euler_fn(const Eigen::Matrix<T, Eigen::Dynamic, 1>& x) {
  Eigen::Matrix<T, Eigen::Dynamic, 1> e(1);
  const Vec4<T> l = x.template head<4>();
  e(0) = euler_parameter_constraint<T>(l);
  return e;
}

// A random spatial beam: reference, and a deformed configuration (14 coordinates).
struct SpatialCase {
  SpatialBeamReference ref;
  VecX x0, x;
};
SpatialCase random_spatial(std::mt19937& rng, double perturbation) {
  SpatialCase c;
  const Eigen::Vector3d xp = randn3(rng), dir = randn3(rng).normalized();
  const double L = 0.5 + std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  const Eigen::Vector3d xq = xp + L * dir;
  const Eigen::Vector4d lp = flexloop::test::random_unit_quaternion(rng),
                        lq = flexloop::test::random_unit_quaternion(rng);
  c.ref = make_spatial_beam_reference(xp, lp, xq, lq, randn3(rng));
  c.x0.resize(14);
  c.x0 << xp, lp, xq, lq;
  c.x = c.x0;
  std::normal_distribution<double> n(0.0, perturbation);
  for (int i : {0, 1, 2, 7, 8, 9}) c.x(i) += n(rng);
  c.x.segment<4>(3) = (lp + Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng))).normalized();
  c.x.segment<4>(10) = (lq + Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng))).normalized();
  return c;
}

struct PlanarCase {
  PlanarBeamReference ref;
  VecX x0, x;
};
PlanarCase random_planar(std::mt19937& rng, double perturbation) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI);
  PlanarCase c;
  const Eigen::Vector2d xp(n(rng), n(rng));
  const double b = ang(rng), L = 0.5 + std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  const Eigen::Vector2d xq = xp + L * Eigen::Vector2d(std::cos(b), std::sin(b));
  const double pp = ang(rng), pq = ang(rng);
  c.ref = make_planar_beam_reference(xp, pp, xq, pq);
  c.x0.resize(6);
  c.x0 << xp, pp, xq, pq;
  c.x = c.x0;
  for (int i = 0; i < 6; ++i) c.x(i) += perturbation * n(rng);
  return c;
}

// First derivatives by forward AutoDiff.
template <class F>
Eigen::MatrixXd ad_jacobian(F f, const VecX& x) {
  const auto n = x.size();
  Eigen::Matrix<Ad, Eigen::Dynamic, 1> xa(n);
  for (Eigen::Index i = 0; i < n; ++i) xa(i) = Ad(x(i), n, i);
  const auto e = f(xa);
  Eigen::MatrixXd J(e.size(), n);
  for (Eigen::Index k = 0; k < e.size(); ++k) {
    if (e(k).derivatives().size() == n)
      J.row(k) = e(k).derivatives().transpose();
    else
      J.row(k).setZero();
  }
  return J;
}

template <class F>
Eigen::MatrixXd fd_jacobian(F f, const VecX& x, double h) {
  const VecX e0 = f(x);
  Eigen::MatrixXd J(e0.size(), x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    VecX xp = x, xm = x;
    xp(i) += h, xm(i) -= h;
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

// Every entry within tol relative to the largest entry.
void check_close(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double tol) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  INFO("AD:\n" << a << "\nFD:\n" << b);
  CHECK((a - b).cwiseAbs().maxCoeff() <= tol * scale);
}

// Directional derivatives d^k/dt^k f(x + t v) at t = 0 (k = 1, 2, 3) from 1-, 2- and 3-level
// nested AutoDiff with one derivative direction at every level.
template <class T>
T seeded(double x, double v) {
  if constexpr (std::is_arithmetic_v<T>) {
    return x;
  } else {
    using S = typename T::Scalar;
    typename T::DerType d(1);
    d(0) = seeded<S>(v, 0.0);  // the derivative of x + t v is v, whose own derivative is 0
    return T(seeded<S>(x, v), d);
  }
}
template <class T>
double innermost(const T& y, int order) {  // d^order/dt^order of y
  if constexpr (std::is_arithmetic_v<T>) {
    return y;
  } else {
    if (order == 0) return innermost(y.value(), 0);
    return y.derivatives().size() ? innermost(y.derivatives()(0), order - 1) : 0.0;
  }
}
template <class T, class F>
VecX directional(F f, const VecX& x, const VecX& v, int order) {
  Eigen::Matrix<T, Eigen::Dynamic, 1> xa(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) xa(i) = seeded<T>(x(i), v(i));
  const auto e = f(xa);
  VecX r(e.size());
  for (Eigen::Index k = 0; k < e.size(); ++k) r(k) = innermost(e(k), order);
  return r;
}

}  // namespace

TEST_CASE("deformations vanish in the undeformed configuration", "[elements][kinematics]") {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 50; ++trial) {
    const SpatialCase s = random_spatial(rng, 0.0);
    CHECK(spatial_fn<double>(s.x0, s.ref).cwiseAbs().maxCoeff() < 1e-14);
    const PlanarCase p = random_planar(rng, 0.0);
    CHECK(planar_fn<double>(p.x0, p.ref).cwiseAbs().maxCoeff() < 1e-14);
    VecX xt(6);
    xt << s.x0.segment<3>(0), s.x0.segment<3>(7);
    CHECK(std::abs(truss_fn<double>(xt, s.ref.l0)(0)) < 1e-14);
    CHECK(std::abs(euler_fn<double>(VecX(s.x0.segment<4>(3)))(0)) < 1e-15);
  }
}

TEST_CASE("spatial reference: body-frame axes are orthonormal and match the y hint",
          "[elements][kinematics]") {
  const Eigen::Vector3d xp(1, 2, 3), xq(1, 2, 5);  // axis along +z
  const Eigen::Vector4d id(1, 0, 0, 0);
  const SpatialBeamReference r =
      make_spatial_beam_reference(xp, id, xq, id, Eigen::Vector3d(1, 0, 0.7));
  CHECK(r.l0 == Approx(2.0));
  CHECK((r.y_p - Eigen::Vector3d(1, 0, 0)).norm() < 1e-15);  // hint minus its axial part
  CHECK((r.z_p - Eigen::Vector3d(0, 1, 0)).norm() < 1e-15);  // e_x x e_y = z x x = y
  CHECK_THROWS_AS(make_spatial_beam_reference(xp, id, xp, id, Eigen::Vector3d(1, 0, 0)),
                  std::invalid_argument);
  CHECK_THROWS_AS(make_spatial_beam_reference(xp, id, xq, id, Eigen::Vector3d(0, 0, -3)),
                  std::invalid_argument);
  CHECK_THROWS_AS(make_spatial_beam_reference(xp, id, xq, id, Eigen::Vector3d::Zero()),
                  std::invalid_argument);
  CHECK_THROWS_AS(
      make_planar_beam_reference(Eigen::Vector2d(1, 1), 0.0, Eigen::Vector2d(1, 1), 0.0),
      std::invalid_argument);
}

TEST_CASE("exact deformations for simple finite motions", "[elements][kinematics]") {
  // Beam along global x, cross-section y = global y, node frames = global frame.
  const double L = 1.3;
  const Eigen::Vector4d id(1, 0, 0, 0);
  const SpatialBeamReference ref = make_spatial_beam_reference(
      Eigen::Vector3d::Zero(), id, Eigen::Vector3d(L, 0, 0), id, Eigen::Vector3d::UnitY());
  auto quat = [](const Eigen::Vector3d& axis, double a) {
    return Eigen::Vector4d(std::cos(a / 2), std::sin(a / 2) * axis(0), std::sin(a / 2) * axis(1),
                           std::sin(a / 2) * axis(2));
  };
  const double a = 0.8;
  VecX x(14);
  // Twist of q by a: e2 = l0 sin a, nothing else.
  x << 0, 0, 0, id, L, 0, 0, quat(Eigen::Vector3d::UnitX(), a);
  VecX expected = VecX::Zero(6);
  expected(1) = L * std::sin(a);
  CHECK((spatial_fn<double>(x, ref) - expected).cwiseAbs().maxCoeff() < 1e-15);
  // q rotated about z by a: R_z(a) e_y = (-sin a, cos a, 0), e6 = -(e_y^q, l) = L sin a.
  // q rotated about y by a: R_y(a) e_z = (sin a, 0, cos a), e4 = (e_z^q, l) = L sin a.
  x << 0, 0, 0, id, L, 0, 0, quat(Eigen::Vector3d::UnitZ(), a);
  expected.setZero();
  expected(5) = L * std::sin(a);
  CHECK((spatial_fn<double>(x, ref) - expected).cwiseAbs().maxCoeff() < 1e-15);
  x << 0, 0, 0, id, L, 0, 0, quat(Eigen::Vector3d::UnitY(), a);
  expected.setZero();
  expected(3) = L * std::sin(a);
  CHECK((spatial_fn<double>(x, ref) - expected).cwiseAbs().maxCoeff() < 1e-15);
  // Stretch along the axis: only e1.
  x << 0, 0, 0, id, L + 0.25, 0, 0, id;
  expected.setZero();
  expected(0) = 0.25;
  CHECK((spatial_fn<double>(x, ref) - expected).cwiseAbs().maxCoeff() < 1e-15);
  // Planar: p turned by a (counter-clockwise), chord fixed: e2 = l0 sin a; q: e3 = -l0 sin a.
  const PlanarBeamReference pr =
      make_planar_beam_reference(Eigen::Vector2d(0, 0), 0.3, Eigen::Vector2d(L, 0), -1.1);
  VecX xpl(6);
  xpl << 0, 0, 0.3 + a, L, 0, -1.1;
  CHECK(
      (planar_fn<double>(xpl, pr) - Eigen::Vector3d(0, L * std::sin(a), 0)).cwiseAbs().maxCoeff() <
      1e-15);
  xpl << 0, 0, 0.3, L, 0, -1.1 + a;
  CHECK(
      (planar_fn<double>(xpl, pr) - Eigen::Vector3d(0, 0, -L * std::sin(a))).cwiseAbs().maxCoeff() <
      1e-15);
}

TEST_CASE("deformations are invariant under finite rigid-body motions", "[elements][kinematics]") {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI);
  std::normal_distribution<double> n(0.0, 1.0);
  double max_change = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    // Global rotation: random (angles up to pi), and every tenth exactly a half turn.
    Eigen::Vector4d g = flexloop::test::random_unit_quaternion(rng);
    if (trial % 10 == 0) g << 0.0, randn3(rng).normalized();
    const Eigen::Matrix3d Q = Eigen::Quaterniond(g(0), g(1), g(2), g(3)).toRotationMatrix();
    const Eigen::Vector3d t = 3.0 * randn3(rng);

    const SpatialCase s = random_spatial(rng, 0.3);  // deformed: |e| = O(0.1 .. 1)
    VecX moved = s.x;
    for (int node : {0, 7}) {
      moved.segment<3>(node) = Q * s.x.segment<3>(node) + t;
      moved.segment<4>(node + 3) = rotate_lambda(g, s.x.segment<4>(node + 3));
    }
    const VecX e = spatial_fn<double>(s.x, s.ref), em = spatial_fn<double>(moved, s.ref);
    REQUIRE(e.norm() > 1e-2);
    max_change = std::max(max_change, (em - e).cwiseAbs().maxCoeff());
    CHECK((em - e).cwiseAbs().maxCoeff() < 1e-12);

    VecX xt(6), xtm(6);
    xt << s.x.segment<3>(0), s.x.segment<3>(7);
    xtm << moved.segment<3>(0), moved.segment<3>(7);
    CHECK(std::abs(truss_fn<double>(xtm, s.ref.l0)(0) - truss_fn<double>(xt, s.ref.l0)(0)) < 1e-12);

    const PlanarCase p = random_planar(rng, 0.3);
    const double al = trial % 10 == 0 ? M_PI : ang(rng);
    const Eigen::Matrix2d Q2 = Eigen::Rotation2Dd(al).toRotationMatrix();
    const Eigen::Vector2d t2(3 * n(rng), 3 * n(rng));
    VecX pm = p.x;
    pm.segment<2>(0) = Q2 * p.x.segment<2>(0) + t2;
    pm.segment<2>(3) = Q2 * p.x.segment<2>(3) + t2;
    pm(2) += al, pm(5) += al;
    const VecX ep = planar_fn<double>(p.x, p.ref);
    REQUIRE(ep.norm() > 1e-2);
    CHECK((planar_fn<double>(pm, p.ref) - ep).cwiseAbs().maxCoeff() < 1e-12);
  }
  INFO("largest change of a spatial beam deformation: " << max_change);
  CHECK(max_change < 1e-12);
}

TEST_CASE("AutoDiff values equal double values, first derivatives equal central differences",
          "[elements][kinematics][autodiff]") {
  std::mt19937 rng(23);
  const double h = 1e-6, tol = 1e-7;
  for (int trial = 0; trial < 10; ++trial) {
    const SpatialCase s = random_spatial(rng, 0.3);
    auto fs = [&](const auto& x) { return spatial_fn(x, s.ref); };
    {
      Eigen::Matrix<Ad, Eigen::Dynamic, 1> xa(14);
      for (int i = 0; i < 14; ++i) xa(i) = Ad(s.x(i), 14, i);
      const auto ea = fs(xa);
      const VecX ed = fs(s.x);
      // The same arithmetic, to rounding: the compiler may fuse multiply-adds in one
      // instantiation and not in the other.
      for (int k = 0; k < 6; ++k)
        CHECK(std::abs(ea(k).value() - ed(k)) <= 8 * 2.2e-16 * std::max(1.0, std::abs(ed(k))));
    }
    check_close(ad_jacobian(fs, s.x), fd_jacobian(fs, s.x, h), tol);

    const PlanarCase p = random_planar(rng, 0.3);
    auto fp = [&](const auto& x) { return planar_fn(x, p.ref); };
    check_close(ad_jacobian(fp, p.x), fd_jacobian(fp, p.x, h), tol);

    VecX xt(6);
    xt << s.x.segment<3>(0), s.x.segment<3>(7);
    auto ft = [&](const auto& x) { return truss_fn(x, s.ref.l0); };
    check_close(ad_jacobian(ft, xt), fd_jacobian(ft, xt, h), tol);

    const VecX lam = 1.3 * s.x.segment<4>(3);  // off the unit sphere as well
    auto fe = [](const auto& x) { return euler_fn(x); };
    check_close(ad_jacobian(fe, lam), fd_jacobian(fe, lam, h), tol);
    // d(lambda.lambda - 1) = 2 lambda^T exactly.
    CHECK((ad_jacobian(fe, lam).transpose() - 2.0 * lam).norm() < 1e-15);
  }
}

TEST_CASE(
    "nested AutoDiff: second and third directional derivatives equal differences of the lower "
    "order",
    "[elements][kinematics][autodiff]") {
  std::mt19937 rng(24);
  const double h = 1e-5;
  for (int trial = 0; trial < 5; ++trial) {
    const SpatialCase s = random_spatial(rng, 0.3);
    const PlanarCase p = random_planar(rng, 0.3);
    auto fs = [&](const auto& x) { return spatial_fn(x, s.ref); };
    auto fp = [&](const auto& x) { return planar_fn(x, p.ref); };
    auto check_function = [&](auto f, const VecX& x) {
      VecX v(x.size());
      for (Eigen::Index i = 0; i < v.size(); ++i)
        v(i) = std::normal_distribution<double>(0, 1)(rng);
      // Order 0 of every type reproduces the double value.
      const VecX e0 = f(x);
      CHECK((directional<Ad3>(f, x, v, 0) - e0).cwiseAbs().maxCoeff() < 1e-14);
      for (int order = 1; order <= 3; ++order) {
        VecX ad;
        VecX lower_p, lower_m;
        const VecX xp = x + h * v, xm = x - h * v;
        if (order == 1) {
          ad = directional<Ad>(f, x, v, 1);
          lower_p = f(xp), lower_m = f(xm);
        } else if (order == 2) {
          ad = directional<Ad2>(f, x, v, 2);
          lower_p = directional<Ad>(f, xp, v, 1), lower_m = directional<Ad>(f, xm, v, 1);
        } else {
          ad = directional<Ad3>(f, x, v, 3);
          lower_p = directional<Ad2>(f, xp, v, 2), lower_m = directional<Ad2>(f, xm, v, 2);
        }
        const VecX fd = (lower_p - lower_m) / (2 * h);
        INFO("order " << order << " AD " << ad.transpose() << " FD " << fd.transpose());
        CHECK((ad - fd).cwiseAbs().maxCoeff() <= 1e-7 * std::max(1.0, fd.cwiseAbs().maxCoeff()));
      }
      // The 2-level type with a full Hessian seeding (as the linearisation uses it) agrees with
      // the directional second derivative: v^T H v.
      const auto n = x.size();
      Eigen::Matrix<Ad2, Eigen::Dynamic, 1> xa(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        xa(i).value() = Ad(x(i), n, i);
        xa(i).derivatives() = Eigen::Matrix<Ad, Eigen::Dynamic, 1>::Zero(n);
        for (Eigen::Index j = 0; j < n; ++j)
          xa(i).derivatives()(j) = Ad(i == j ? 1.0 : 0.0, VecX::Zero(n));
      }
      const auto e = f(xa);
      const VecX d2 = directional<Ad2>(f, x, v, 2);
      for (Eigen::Index k = 0; k < e.size(); ++k) {
        Eigen::MatrixXd H(n, n);
        for (Eigen::Index i = 0; i < n; ++i)
          H.row(i) = e(k).derivatives()(i).derivatives().transpose();
        CHECK((H - H.transpose()).cwiseAbs().maxCoeff() < 1e-12);
        CHECK(v.dot(H * v) == Approx(d2(k)).margin(1e-12));
      }
    };
    check_function(fs, s.x);
    check_function(fp, p.x);
  }
}
