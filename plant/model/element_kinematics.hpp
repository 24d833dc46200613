// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Element deformation functions e = D(x) (SPACAR-style finite elements).
//
// Sources: J.B. Jonker, "A finite element dynamic analysis of spatial mechanisms with flexible
// links", CMAME 76 (1989) 17-40; J.B. Jonker, J.P. Meijaard, "SPACAR - computer program for dynamic
// analysis of flexible spatial mechanisms and manipulators", in W. Schiehlen (ed.), Multibody
// Systems Handbook, Springer 1990, 123-143; flexloop doc/design.md §3.
//
// Truss:   e1 = |l| - l0,  l = xq - xp.
//
// Spatial beam. Nodes p, q carry positions x and Euler parameters lambda (rotation.hpp). Rigidly
// attached to each node is an orthonormal triad (e_x, e_y, e_z); in the undeformed state e_x lies
// along the beam axis and e_y, e_z along the principal axes of the cross-section. Only e_y and
// e_z enter the deformations: e_y^p = R(lambda_p) y_p etc., with the body-frame components y_p,
// z_p, y_q, z_q fixed by make_spatial_beam_reference. With l = xq - xp:
//   e1 = |l| - l0                                       elongation
//   e2 = l0 ((e_z^p, e_y^q) - (e_y^p, e_z^q)) / 2        torsion
//   e3 = -(e_z^p, l),  e4 = (e_z^q, l)                   bending in the x-z plane (about y)
//   e5 =  (e_y^p, l),  e6 = -(e_y^q, l)                  bending in the x-y plane (about z)
// These are Jonker's (1989) definitions as quoted in doc/design.md §3, unscaled: all six have the
// dimension of length (the primary text could not be consulted when this was written; the
// small-deformation meaning below and the stiffness are proved by tests/elements). For
// small deformations, with phi the twist of q relative to p and theta_p, theta_q the end
// rotations relative to the chord (right-handed, about the beam's y or z axis),
//   e2 = l0 phi,  e3 = -l0 theta_py,  e4 = l0 theta_qy,  e5 = -l0 theta_pz,  e6 = l0 theta_qz,
// so a uniform bending moment (theta_p = -theta_q) gives e3 = e4 and e5 = e6. The matching
// stiffness is in element_properties.hpp.
//
// Planar beam (doc/design.md §3): nodes carry (x, y, phi), R(phi) the 2-D rotation, and n_y the
// cross-section axis (the beam axis turned +90 degrees) in each node's frame at the undeformed
// state:
//   e1 = |l| - l0,  e2 = -(R(phi_p) n_y^p, l),  e3 = (R(phi_q) n_y^q, l).
// Small deformations: e2 = l0 theta_p, e3 = -l0 theta_q (theta counter-clockwise, relative to
// the chord).
//
// Euler parameter constraint: lambda.lambda - 1, always rigid.
//
// Every template works for T = double, Eigen::AutoDiffScalar<Eigen::VectorXd> and the nested
// AutoDiffScalar<Matrix<AutoDiffScalar<VectorXd>, Dynamic, 1>>: no branches on T, no abs/atan2.
// All deformations vanish in the undeformed configuration and are invariant under rigid motions.
#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "plant/model/rotation.hpp"

namespace flexloop::plant::model {

namespace element_detail {

// Arithmetic with double constants that works at any AutoDiff nesting depth. Eigen's mixed
// AutoDiffScalar * double operators exist only for one level of nesting, so a constant is
// applied to the value and, recursively, to every derivative instead. T is double or an
// Eigen::AutoDiffScalar (anything with value(), derivatives() and DerType).
template <class T>
T scale(const T& x, double c) {
  if constexpr (std::is_arithmetic_v<T>) {
    return x * c;
  } else {
    using Der = typename T::DerType;
    const Der d = x.derivatives().unaryExpr(
        [c](const typename Der::Scalar& di) { return scale<typename Der::Scalar>(di, c); });
    return T(scale(x.value(), c), d);
  }
}

template <class T>
T add(const T& x, double c) {
  if constexpr (std::is_arithmetic_v<T>) {
    return x + c;
  } else {
    return T(add(x.value(), c), x.derivatives());
  }
}

// R v for a constant body-frame vector v.
template <class T>
Vec3<T> rotate_constant(const Eigen::Matrix<T, 3, 3>& R, const Eigen::Vector3d& v) {
  Vec3<T> r;
  for (int i = 0; i < 3; ++i)
    r(i) = scale(R(i, 0), v(0)) + scale(R(i, 1), v(1)) + scale(R(i, 2), v(2));
  return r;
}

template <class T, int N>
T dot(const Eigen::Matrix<T, N, 1>& a, const Eigen::Matrix<T, N, 1>& b) {
  T s = a(0) * b(0);
  for (int i = 1; i < N; ++i) s = s + a(i) * b(i);
  return s;
}

}  // namespace element_detail

/// e1 = |xq - xp| - l0.
template <class T>
T truss_elongation(const Vec3<T>& xp, const Vec3<T>& xq, double l0) {
  using std::sqrt;
  const Vec3<T> l = xq - xp;
  return element_detail::add<T>(sqrt(element_detail::dot<T, 3>(l, l)), -l0);
}

/// lambda.lambda - 1 (the normalisation of a node's Euler parameters, a rigid "deformation").
template <class T>
T euler_parameter_constraint(const Vec4<T>& lambda) {
  return element_detail::add<T>(element_detail::dot<T, 4>(lambda, lambda), -1.0);
}

/// Undeformed state of a spatial beam: l0 and the cross-section axes y, z in each node's BODY
/// frame.
struct SpatialBeamReference {
  double l0;
  Eigen::Vector3d y_p, z_p, y_q, z_q;
};

/// Reference from the undeformed configuration. The beam's global axes: e_x = (xq - xp)/l0,
/// e_y = y_hint orthogonalised against e_x and normalised, e_z = e_x x e_y; then y_p = R_p^T e_y,
/// z_p = R_p^T e_z and likewise at q (R of the normalised lambdas). Throws std::invalid_argument
/// on a zero length, on y_hint (nearly) parallel to the axis (sine of the angle < 1e-6), or on a
/// zero or non-finite lambda.
inline SpatialBeamReference make_spatial_beam_reference(const Eigen::Vector3d& xp,
                                                        const Eigen::Vector4d& lambda_p,
                                                        const Eigen::Vector3d& xq,
                                                        const Eigen::Vector4d& lambda_q,
                                                        const Eigen::Vector3d& y_hint) {
  const Eigen::Vector3d l = xq - xp;
  const double l0 = l.norm();
  if (!(l0 > 0.0) || !std::isfinite(l0))
    throw std::invalid_argument("spatial beam: nodes coincide (zero length)");
  const Eigen::Vector3d ex = l / l0;
  const double hn = y_hint.norm();
  if (!(hn > 0.0) || !std::isfinite(hn))
    throw std::invalid_argument("spatial beam: y axis hint is zero or not finite");
  const Eigen::Vector3d h = y_hint / hn;
  const Eigen::Vector3d yperp = h - h.dot(ex) * ex;
  if (yperp.norm() < 1e-6)
    throw std::invalid_argument("spatial beam: y axis hint is parallel to the beam axis");
  const Eigen::Vector3d ey = yperp.normalized();
  const Eigen::Vector3d ez = ex.cross(ey);
  auto body_rotation = [](const Eigen::Vector4d& lam) {
    const double n = lam.norm();
    if (!(n > 0.0) || !std::isfinite(n))
      throw std::invalid_argument("spatial beam: Euler parameters are zero or not finite");
    return rotation_matrix<double>(lam / n);
  };
  const Eigen::Matrix3d Rp = body_rotation(lambda_p), Rq = body_rotation(lambda_q);
  return {l0, Rp.transpose() * ey, Rp.transpose() * ez, Rq.transpose() * ey, Rq.transpose() * ez};
}

/// The six spatial beam deformations (e1..e6 above), in the order (elongation, torsion,
/// bending -(e_z^p, l), (e_z^q, l), (e_y^p, l), -(e_y^q, l)).
template <class T>
Eigen::Matrix<T, 6, 1> spatial_beam_deformations(const Vec3<T>& xp, const Vec4<T>& lambda_p,
                                                 const Vec3<T>& xq, const Vec4<T>& lambda_q,
                                                 const SpatialBeamReference& ref) {
  using element_detail::add;
  using element_detail::dot;
  using element_detail::rotate_constant;
  using element_detail::scale;
  using std::sqrt;
  const Vec3<T> l = xq - xp;
  const Eigen::Matrix<T, 3, 3> Rp = rotation_matrix<T>(lambda_p);
  const Eigen::Matrix<T, 3, 3> Rq = rotation_matrix<T>(lambda_q);
  const Vec3<T> yp = rotate_constant<T>(Rp, ref.y_p), zp = rotate_constant<T>(Rp, ref.z_p);
  const Vec3<T> yq = rotate_constant<T>(Rq, ref.y_q), zq = rotate_constant<T>(Rq, ref.z_q);
  Eigen::Matrix<T, 6, 1> e;
  e(0) = add<T>(sqrt(dot<T, 3>(l, l)), -ref.l0);
  e(1) = scale<T>(dot<T, 3>(zp, yq) - dot<T, 3>(yp, zq), 0.5 * ref.l0);
  e(2) = -dot<T, 3>(zp, l);
  e(3) = dot<T, 3>(zq, l);
  e(4) = dot<T, 3>(yp, l);
  e(5) = -dot<T, 3>(yq, l);
  return e;
}

/// Undeformed state of a planar beam: length l0, nodal angles phi_p0, phi_q0 and beam axis
/// angle beta (the axis e_x = (cos beta, sin beta)). The cross-section axis in node i's frame is
/// n_y^i = R(phi_i0)^T (-sin beta, cos beta), so R(phi_i) n_y^i is the direction at the angle
/// beta + pi/2 + (phi_i - phi_i0).
struct PlanarBeamReference {
  double l0;
  double phi_p0, phi_q0;
  double beta;
};

/// Throws std::invalid_argument on a zero length.
inline PlanarBeamReference make_planar_beam_reference(const Eigen::Vector2d& xp, double phi_p,
                                                      const Eigen::Vector2d& xq, double phi_q) {
  const Eigen::Vector2d l = xq - xp;
  const double l0 = l.norm();
  if (!(l0 > 0.0) || !std::isfinite(l0))
    throw std::invalid_argument("planar beam: nodes coincide (zero length)");
  return {l0, phi_p, phi_q, std::atan2(l(1), l(0))};
}

/// (e1, e2, e3) = (|l| - l0, -(R_p n_y^p, l), (R_q n_y^q, l)).
template <class T>
Eigen::Matrix<T, 3, 1> planar_beam_deformations(const Vec2<T>& xp, const T& phi_p,
                                                const Vec2<T>& xq, const T& phi_q,
                                                const PlanarBeamReference& ref) {
  using element_detail::add;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const Vec2<T> l = xq - xp;
  // Angle of the rotated cross-section axis minus pi/2: n = (-sin a, cos a).
  const T ap = add<T>(phi_p, ref.beta - ref.phi_p0);
  const T aq = add<T>(phi_q, ref.beta - ref.phi_q0);
  Eigen::Matrix<T, 3, 1> e;
  e(0) = add<T>(sqrt(l(0) * l(0) + l(1) * l(1)), -ref.l0);
  e(1) = sin(ap) * l(0) - cos(ap) * l(1);
  e(2) = cos(aq) * l(1) - sin(aq) * l(0);
  return e;
}

}  // namespace flexloop::plant::model
