// SPDX-License-Identifier: BSD-3-Clause
// Euler parameters: R(lambda) against Eigen's own quaternion and angle-axis code, Shepperd
// inverse round trip (including angles at and near pi), and composition.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "plant/model/rotation.hpp"
#include "tests/support/random_rotation.hpp"

using namespace flexloop::plant::model;

namespace {

// (cos(a/2), sin(a/2) axis): the textbook definition, independent of the code under test.
Eigen::Vector4d from_axis_angle(const Eigen::Vector3d& axis, double a) {
  Eigen::Vector4d l;
  l << std::cos(a / 2), std::sin(a / 2) * axis.normalized();
  return l;
}

double sign_insensitive_distance(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return std::min((a - b).norm(), (a + b).norm());
}

}  // namespace

TEST_CASE("rotation_matrix equals Eigen's quaternion and angle-axis rotations", "[rotation]") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector4d l = flexloop::test::random_unit_quaternion(rng);
    const Eigen::Matrix3d R = rotation_matrix<double>(l);
    const Eigen::Quaterniond q(l(0), l(1), l(2), l(3));
    CHECK((R - q.toRotationMatrix()).norm() < 1e-14);
    CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-14);
    CHECK(R.determinant() == Approx(1.0).margin(1e-14));
  }
  // A known rotation: +90 degrees about z maps x to y.
  const Eigen::Matrix3d Rz =
      rotation_matrix<double>(from_axis_angle(Eigen::Vector3d::UnitZ(), M_PI / 2));
  CHECK((Rz * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm() < 1e-15);
  // Angle-axis, angles up to pi.
  std::uniform_real_distribution<double> ang(0.0, M_PI);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    const double a = ang(rng);
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(a, axis).toRotationMatrix();
    CHECK((rotation_matrix<double>(from_axis_angle(axis, a)) - expected).norm() < 1e-14);
  }
}

TEST_CASE("rotation_matrix is homogeneous quadratic off the unit sphere", "[rotation]") {
  std::mt19937 rng(12);
  const Eigen::Vector4d l = flexloop::test::random_unit_quaternion(rng);
  const double c = 1.7;
  CHECK((rotation_matrix<double>(c * l) - c * c * rotation_matrix<double>(l)).norm() < 1e-13);
}

TEST_CASE("euler_parameters_from_rotation round-trips, including angles near pi", "[rotation]") {
  std::mt19937 rng(13);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> ang(0.0, M_PI);
  auto check_round_trip = [](const Eigen::Vector3d& axis, double a) {
    const Eigen::Vector4d expected = from_axis_angle(axis, a);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(a, axis.normalized()).toRotationMatrix();
    const Eigen::Vector4d l = euler_parameters_from_rotation(R);
    INFO("angle " << a << " axis " << axis.transpose());
    CHECK(std::abs(l.norm() - 1.0) < 1e-15 * 10);
    CHECK(sign_insensitive_distance(l, expected) < 1e-13);
    CHECK(l(0) >= 0.0);
  };
  for (int trial = 0; trial < 200; ++trial)
    check_round_trip(Eigen::Vector3d(n(rng), n(rng), n(rng)), ang(rng));
  // Each branch of Shepperd's method and the hard cases: 0, tiny, pi, pi - tiny.
  for (const Eigen::Vector3d& axis :
       {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1),
        Eigen::Vector3d(1, -2, 0.5), Eigen::Vector3d(-0.3, 0.1, 2.0)}) {
    for (double a : {0.0, 1e-12, 1e-6, 1.0, 2.5, M_PI - 1e-6, M_PI - 1e-12, M_PI})
      check_round_trip(axis, a);
  }
}

TEST_CASE("quaternion_product composes rotations", "[rotation]") {
  std::mt19937 rng(14);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector4d a = flexloop::test::random_unit_quaternion(rng),
                          b = flexloop::test::random_unit_quaternion(rng);
    const Eigen::Vector4d ab = quaternion_product(a, b);
    const Eigen::Matrix3d Ra = Eigen::Quaterniond(a(0), a(1), a(2), a(3)).toRotationMatrix();
    const Eigen::Matrix3d Rb = Eigen::Quaterniond(b(0), b(1), b(2), b(3)).toRotationMatrix();
    CHECK((rotation_matrix<double>(ab) - Ra * Rb).norm() < 1e-14);
    const Eigen::Quaterniond qab =
        Eigen::Quaterniond(a(0), a(1), a(2), a(3)) * Eigen::Quaterniond(b(0), b(1), b(2), b(3));
    CHECK((ab - Eigen::Vector4d(qab.w(), qab.x(), qab.y(), qab.z())).norm() < 1e-15 * 10);
  }
  // Two quarter turns about z make a half turn.
  const Eigen::Vector4d qz = from_axis_angle(Eigen::Vector3d::UnitZ(), M_PI / 2);
  const Eigen::Vector4d half = quaternion_product(qz, qz);
  CHECK(sign_insensitive_distance(half, Eigen::Vector4d(0, 0, 0, 1)) < 1e-15 * 10);
}
