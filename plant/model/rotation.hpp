// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Euler parameters (unit quaternion, scalar first): lambda = (l0, l1, l2, l3) = (cos(a/2), sin(a/2)
// n) for a rotation by angle a about the unit axis n.
//
//   R(lambda) = (l0^2 - v.v) I + 2 v v^T + 2 l0 [v]x,   v = (l1, l2, l3),  [v]x w = v x w,
//
// i.e. R(lambda) w = lambda * (0, w) * conj(lambda). R maps body-frame components to global ones.
// The form is homogeneous quadratic in lambda, so off the unit sphere R(c lambda) = c^2 R(lambda):
// it stays a scaled rotation, and R(a * b) = R(a) R(b) holds for any a, b. The linearisation
// enforces |lambda| = 1 through euler_parameter_constraint (element_kinematics.hpp), so the
// extension off the sphere does not change the transfer functions. Sources: J.B. Jonker, CMAME 76
// (1989) 17-40, §2; A.L. Schwab, J.P. Meijaard, "How to draw Euler angles and utilize Euler
// parameters", DETC2006-99307 (quaternion product and R(lambda)). Inverse: S.W. Shepperd,
// "Quaternion from rotation matrix", J. Guidance Control 1 (1978) 223-224.
#include <Eigen/Dense>
#include <cmath>

namespace flexloop::plant::model {

template <class T>
using Vec2 = Eigen::Matrix<T, 2, 1>;
template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
template <class T>
using Vec4 = Eigen::Matrix<T, 4, 1>;

/// R(lambda), body to global, for unit lambda (see the header comment for non-unit lambda).
/// Works for double and Eigen AutoDiff scalars (no branches on T).
template <class T>
Eigen::Matrix<T, 3, 3> rotation_matrix(const Vec4<T>& lambda) {
  const T& a = lambda(0);
  const T& b = lambda(1);
  const T& c = lambda(2);
  const T& d = lambda(3);
  // Sums instead of 2.0 * x keep this free of mixed double/T operators (any AutoDiff nesting).
  const T s = a * a - b * b - c * c - d * d;
  const T bb = b * b, cc = c * c, dd = d * d;
  const T bc_m = b * c - a * d, bc_p = b * c + a * d;
  const T bd_m = b * d - a * c, bd_p = b * d + a * c;
  const T cd_m = c * d - a * b, cd_p = c * d + a * b;
  Eigen::Matrix<T, 3, 3> R;
  R(0, 0) = s + bb + bb;
  R(1, 1) = s + cc + cc;
  R(2, 2) = s + dd + dd;
  R(0, 1) = bc_m + bc_m;
  R(1, 0) = bc_p + bc_p;
  R(0, 2) = bd_p + bd_p;
  R(2, 0) = bd_m + bd_m;
  R(1, 2) = cd_m + cd_m;
  R(2, 1) = cd_p + cd_p;
  return R;
}

/// a * b (Hamilton product, scalar first): R(a * b) = R(a) R(b).
inline Eigen::Vector4d quaternion_product(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  const Eigen::Vector3d av = a.tail<3>(), bv = b.tail<3>();
  Eigen::Vector4d r;
  r(0) = a(0) * b(0) - av.dot(bv);
  r.tail<3>() = a(0) * bv + b(0) * av + av.cross(bv);
  return r;
}

/// Unit Euler parameters of a rotation matrix (Shepperd's method: take the square root of the
/// largest of 4 l0^2, 4 l1^2, 4 l2^2, 4 l3^2, so there is no cancellation near a = pi). The sign
/// is chosen so that l0 >= 0. R is assumed orthonormal with det +1 (a loose R is tolerated: the
/// result is normalised).
inline Eigen::Vector4d euler_parameters_from_rotation(const Eigen::Matrix3d& R) {
  const double tr = R.trace();
  // 4 l_i^2 = 1 + 2 R_ii - tr (i = 1..3), 4 l0^2 = 1 + tr.
  const Eigen::Vector4d four_sq(1.0 + tr, 1.0 + 2.0 * R(0, 0) - tr, 1.0 + 2.0 * R(1, 1) - tr,
                                1.0 + 2.0 * R(2, 2) - tr);
  Eigen::Index k = 0;
  four_sq.maxCoeff(&k);
  Eigen::Vector4d l;
  const double lk = 0.5 * std::sqrt(four_sq(k));
  const double f = 0.25 / lk;
  switch (k) {
    case 0:
      l << lk, f * (R(2, 1) - R(1, 2)), f * (R(0, 2) - R(2, 0)), f * (R(1, 0) - R(0, 1));
      break;
    case 1:
      l << f * (R(2, 1) - R(1, 2)), lk, f * (R(0, 1) + R(1, 0)), f * (R(0, 2) + R(2, 0));
      break;
    case 2:
      l << f * (R(0, 2) - R(2, 0)), f * (R(0, 1) + R(1, 0)), lk, f * (R(1, 2) + R(2, 1));
      break;
    default:
      l << f * (R(1, 0) - R(0, 1)), f * (R(0, 2) + R(2, 0)), f * (R(1, 2) + R(2, 1)), lk;
      break;
  }
  if (l(0) < 0.0) l = -l;
  return l.normalized();
}

}  // namespace flexloop::plant::model
