// SPDX-License-Identifier: BSD-3-Clause
// Small-displacement beam theory: a cantilever element (p clamped at the reference) is given the
// exact Euler-Bernoulli displacements of a tip force, a tip torque and an axial force, with the
// beam and the node frames in random orientations. Checked: (a) the deformations against the
// end rotations relative to the chord, (b) e^T S e / 2 against the analytic strain energy,
// (c) the nodal forces D^T sigma (sigma = S e) against statics: applied tip load at q, reactions
// at p, no moment at a force-loaded tip.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

#include "plant/model/element_kinematics.hpp"
#include "plant/model/element_properties.hpp"

#include <unsupported/Eigen/AutoDiff>

using namespace flexloop::plant::model;

namespace {

using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using AdVec = Eigen::Matrix<Ad, Eigen::Dynamic, 1>;

Eigen::Vector4d quat(const Eigen::Vector3d& rotation_vector) {  // exp map, scalar first
  const double a = rotation_vector.norm();
  if (a == 0.0) return {1, 0, 0, 0};
  const Eigen::Vector3d n = rotation_vector / a;
  return {std::cos(a / 2), std::sin(a / 2) * n(0), std::sin(a / 2) * n(1), std::sin(a / 2) * n(2)};
}

Eigen::Vector4d compose(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {  // by Eigen
  const Eigen::Quaterniond r =
      Eigen::Quaterniond(a(0), a(1), a(2), a(3)) * Eigen::Quaterniond(b(0), b(1), b(2), b(3));
  return {r.w(), r.x(), r.y(), r.z()};
}

const BeamSection kSection{2.1e11, 8.0e10, 1.0e-4, 2.0e-9, 8.0e-10, 1.5e-9, 7800.0};

struct Cantilever {
  double L;
  Eigen::Vector3d ex, ey, ez;  // beam axes (global), y and z principal
  Eigen::Vector3d xp, xq0;
  Eigen::Vector4d lp, lq0;
  SpatialBeamReference ref;
};

Cantilever random_cantilever(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Cantilever c;
  c.L = 0.7;
  const Eigen::Vector4d beam = Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)).normalized();
  const Eigen::Matrix3d B =
      Eigen::Quaterniond(beam(0), beam(1), beam(2), beam(3)).toRotationMatrix();
  c.ex = B.col(0), c.ey = B.col(1), c.ez = B.col(2);
  c.xp = Eigen::Vector3d(n(rng), n(rng), n(rng));
  c.xq0 = c.xp + c.L * c.ex;
  c.lp = Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)).normalized();
  c.lq0 = Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)).normalized();
  c.ref = make_spatial_beam_reference(c.xp, c.lp, c.xq0, c.lq0,
                                      c.ey + 0.3 * c.ex);  // hint not orthogonal
  return c;
}

struct Loads {
  double N = 0, Py = 0, Pz = 0, T = 0;  // axial force, tip forces along beam y, z; torque about x
};

// Exact Euler-Bernoulli / Saint-Venant tip displacement and rotation of the cantilever.
void tip_state(const Cantilever& c, const Loads& f, Eigen::Vector3d& xq, Eigen::Vector4d& lq,
               Eigen::Vector3d& rot) {
  const BeamSection& s = kSection;
  const double L = c.L;
  const double wy = f.Py * L * L * L / (3 * s.E * s.Iz), ty = f.Py * L * L / (2 * s.E * s.Iz);
  const double wz = f.Pz * L * L * L / (3 * s.E * s.Iy), tz = f.Pz * L * L / (2 * s.E * s.Iy);
  const double u = f.N * L / (s.E * s.A), phi = f.T * L / (s.G * s.J);
  // Linear theory fixes the axial tip displacement only to first order. The second-order part is
  // chosen so that the chord has the length L + N L/(EA): without an axial load the axis does not
  // stretch (otherwise the large EA would turn the O(w^2) chord stretch into a spurious axial
  // force).
  const double axial = std::sqrt((L + u) * (L + u) - wy * wy - wz * wz) - L;
  xq = c.xq0 + axial * c.ex + wy * c.ey + wz * c.ez;
  // Slope ty turns e_x towards e_y (about +z); slope tz turns e_x towards e_z (about -y).
  rot = phi * c.ex + ty * c.ez - tz * c.ey;
  lq = compose(quat(rot), c.lq0);
}

Eigen::Matrix<double, 6, 1> deformations(const Cantilever& c, const Eigen::Vector3d& xq,
                                         const Eigen::Vector4d& lq) {
  return spatial_beam_deformations<double>(c.xp, c.lp, xq, lq, c.ref);
}

// Generalised nodal forces D^T sigma conjugate to (dxp, global rotation increment at p, dxq,
// rotation at q): forces and moments. Node rotations are perturbed as lambda(w) = (1, w/2) *
// lambda, whose first derivative at w = 0 equals that of the exact exponential map.
Eigen::Matrix<double, 12, 1> nodal_forces(const Cantilever& c, const Eigen::Vector3d& xq,
                                          const Eigen::Vector4d& lq,
                                          const Eigen::Matrix<double, 6, 1>& sigma) {
  AdVec z(12);
  for (int i = 0; i < 12; ++i) z(i) = Ad(0.0, 12, i);
  auto perturbed = [](const Eigen::Vector4d& l, const AdVec& w) {
    // (1, w/2) * l: scalar r0 = l0 - w.lv/2, vector lv + l0 w/2 + (w/2) x lv.
    Vec4<Ad> r;
    const Eigen::Vector3d lv = l.tail<3>();
    r(0) = l(0) - 0.5 * (w(0) * lv(0) + w(1) * lv(1) + w(2) * lv(2));
    r(1) = lv(0) + 0.5 * (l(0) * w(0) + w(1) * lv(2) - w(2) * lv(1));
    r(2) = lv(1) + 0.5 * (l(0) * w(1) + w(2) * lv(0) - w(0) * lv(2));
    r(3) = lv(2) + 0.5 * (l(0) * w(2) + w(0) * lv(1) - w(1) * lv(0));
    return r;
  };
  Vec3<Ad> xpa, xqa;
  for (int i = 0; i < 3; ++i) xpa(i) = c.xp(i) + z(i), xqa(i) = xq(i) + z(6 + i);
  const Vec4<Ad> lpa = perturbed(c.lp, z.segment(3, 3)), lqa = perturbed(lq, z.segment(9, 3));
  const auto e = spatial_beam_deformations<Ad>(xpa, lpa, xqa, lqa, c.ref);
  Eigen::Matrix<double, 6, 12> J;
  for (int k = 0; k < 6; ++k) J.row(k) = e(k).derivatives().transpose();
  return J.transpose() * sigma;
}

}  // namespace

TEST_CASE("spatial beam: cantilever under tip loads matches Euler-Bernoulli theory",
          "[elements][beam_theory]") {
  std::mt19937 rng(31);
  const BeamSection& s = kSection;
  const Eigen::Matrix<double, 6, 6> S = spatial_beam_stiffness(s, 0.7);
  CHECK((S - S.transpose()).norm() == 0.0);
  // Small loads: end rotations ~1e-6 rad, so second-order terms are ~1e-6 relative.
  const double L = 0.7;
  const double Py = 2e-6 * s.E * s.Iz / (L * L), Pz = 2e-6 * s.E * s.Iy / (L * L);
  const double T = 1e-6 * s.G * s.J / L, N = 1e-6 * s.E * s.A;

  for (int trial = 0; trial < 10; ++trial) {
    const Cantilever c = random_cantilever(rng);
    Eigen::Vector3d xq, rot;
    Eigen::Vector4d lq;

    for (int load_case = 0; load_case < 5; ++load_case) {
      Loads f;
      if (load_case == 0) f.Py = Py;
      if (load_case == 1) f.Pz = Pz;
      if (load_case == 2) f.T = T;
      if (load_case == 3) f.N = N;
      if (load_case == 4) f = Loads{N, Py, Pz, T};
      tip_state(c, f, xq, lq, rot);
      const Eigen::Matrix<double, 6, 1> e = deformations(c, xq, lq);
      INFO("trial " << trial << " load case " << load_case << " e = " << e.transpose());

      // (a) Deformations vs end rotations relative to the chord (first order). Chord angles:
      // psi_z = wy/L (towards y, about z), psi_y = -wz/L (about y).
      const double wy = f.Py * L * L * L / (3 * s.E * s.Iz), ty = f.Py * L * L / (2 * s.E * s.Iz);
      const double wz = f.Pz * L * L * L / (3 * s.E * s.Iy), tz = f.Pz * L * L / (2 * s.E * s.Iy);
      const double th_pz = -wy / L, th_qz = ty - wy / L;  // about z
      const double th_py = wz / L, th_qy = -tz + wz / L;  // about y
      const double phi = f.T * L / (s.G * s.J), u = f.N * L / (s.E * s.A);
      Eigen::Matrix<double, 6, 1> expected;
      expected << u, L * phi, -L * th_py, L * th_qy, -L * th_pz, L * th_qz;
      const double scale = expected.cwiseAbs().maxCoeff();
      CHECK((e - expected).cwiseAbs().maxCoeff() <= 1e-5 * scale);

      // (b) Strain energy.
      const double U = 0.5 * e.dot(S * e);
      const double U_exact = Py * Py * L * L * L / (6 * s.E * s.Iz) * (f.Py != 0) +
                             Pz * Pz * L * L * L / (6 * s.E * s.Iy) * (f.Pz != 0) +
                             T * T * L / (2 * s.G * s.J) * (f.T != 0) +
                             N * N * L / (2 * s.E * s.A) * (f.N != 0);
      CHECK(U == Approx(U_exact).epsilon(1e-6));

      // (c) Statics: D^T S e are the nodal forces holding the element in this shape: the applied
      // tip load at q (force N ex + Py ey + Pz ez, moment T ex; no bending moment at a free tip),
      // the reactions at p (minus the force, moment -(T ex + L ex x F)).
      const Eigen::Matrix<double, 12, 1> g = nodal_forces(c, xq, lq, S * e);
      const Eigen::Vector3d F = f.N * c.ex + f.Py * c.ey + f.Pz * c.ez;
      const Eigen::Vector3d Mq = f.T * c.ex;
      const Eigen::Vector3d Mp = -(f.T * c.ex + (L * c.ex).cross(F));
      // Bound: second-order terms (1e-6 relative, see the loads) plus rounding: the deformations
      // come from coordinates of size L, so each carries ~eps L of rounding, which the stiffness
      // turns into ~eps L max|S| of force (a load case without axial force still sees the axial
      // stiffness times that rounding).
      const double fscale =
          std::max({std::abs(f.N), std::abs(f.Py), std::abs(f.Pz), std::abs(f.T) / L});
      const double rounding =
          8 * std::numeric_limits<double>::epsilon() * L * S.cwiseAbs().maxCoeff();
      const double bound = 1e-5 * fscale + rounding;
      INFO("forces " << g.transpose() << "; bound " << bound << " (rounding " << rounding << ")");
      CHECK((g.segment<3>(6) - F).norm() <= bound);
      CHECK((g.segment<3>(9) - Mq).norm() <= bound * L);
      CHECK((g.segment<3>(0) + F).norm() <= bound);
      CHECK((g.segment<3>(3) - Mp).norm() <= bound * L);
    }
  }
}

TEST_CASE("spatial beam stiffness is exactly the slope-deflection stiffness",
          "[elements][beam_theory]") {
  // Independent of the kinematics: with e = (u, l0 phi, -l0 tpy, l0 tqy, -l0 tpz, l0 tqz),
  // e^T S e / 2 must equal EA u^2/(2 l0) + GJ phi^2/(2 l0) + sum over planes of
  // (2 EI / l0)(tp^2 + tp tq + tq^2).
  const BeamSection& s = kSection;
  const double l0 = 0.37;
  const Eigen::Matrix<double, 6, 6> S = spatial_beam_stiffness(s, l0);
  std::mt19937 rng(32);
  std::normal_distribution<double> n(0.0, 1e-3);
  for (int trial = 0; trial < 20; ++trial) {
    const double u = n(rng), phi = n(rng), tpy = n(rng), tqy = n(rng), tpz = n(rng), tqz = n(rng);
    Eigen::Matrix<double, 6, 1> e;
    e << u, l0 * phi, -l0 * tpy, l0 * tqy, -l0 * tpz, l0 * tqz;
    const double U = s.E * s.A * u * u / (2 * l0) + s.G * s.J * phi * phi / (2 * l0) +
                     2 * s.E * s.Iy / l0 * (tpy * tpy + tpy * tqy + tqy * tqy) +
                     2 * s.E * s.Iz / l0 * (tpz * tpz + tpz * tqz + tqz * tqz);
    CHECK(0.5 * e.dot(S * e) == Approx(U).epsilon(1e-13));
  }
  CHECK(S.selfadjointView<Eigen::Upper>().ldlt().isPositive());
  CHECK_THROWS_AS(spatial_beam_stiffness(s, 0.0), std::invalid_argument);
}

TEST_CASE("planar beam: cantilever under tip loads matches Euler-Bernoulli theory",
          "[elements][beam_theory]") {
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI);
  const double E = 7.0e10, A = 2.0e-4, I = 3.0e-9, L = 0.45;
  const Eigen::Matrix3d S = planar_beam_stiffness(E, A, I, L);
  const double P = 2e-6 * E * I / (L * L), N = 1e-6 * E * A;
  using Ad = Eigen::AutoDiffScalar<Eigen::VectorXd>;
  for (int trial = 0; trial < 10; ++trial) {
    const double beta = ang(rng), php = ang(rng), phq0 = ang(rng);
    const Eigen::Vector2d ex(std::cos(beta), std::sin(beta)), ey(-std::sin(beta), std::cos(beta));
    const Eigen::Vector2d xp(0.3, -1.2), xq0 = xp + L * ex;
    const PlanarBeamReference ref = make_planar_beam_reference(xp, php, xq0, phq0);
    for (int load_case = 0; load_case < 3; ++load_case) {
      const double Pf = load_case != 1 ? P : 0.0, Nf = load_case != 0 ? N : 0.0;
      const double w = Pf * L * L * L / (3 * E * I), t = Pf * L * L / (2 * E * I),
                   u = Nf * L / (E * A);
      // Second-order axial shift so that the chord length is L + u (see tip_state above).
      const double axial = std::sqrt((L + u) * (L + u) - w * w) - L;
      const Eigen::Vector2d xq = xq0 + axial * ex + w * ey;
      const double phq = phq0 + t;
      const Eigen::Vector3d e = planar_beam_deformations<double>(xp, php, xq, phq, ref);
      INFO("trial " << trial << " load case " << load_case << " e = " << e.transpose());
      // (a) e2 = l0 theta_p, e3 = -l0 theta_q (counter-clockwise, relative to the chord w/L).
      const Eigen::Vector3d expected(u, L * (-w / L), -L * (t - w / L));
      CHECK((e - expected).cwiseAbs().maxCoeff() <= 1e-5 * expected.cwiseAbs().maxCoeff());
      // (b) energy.
      const double U_exact = Pf * Pf * L * L * L / (6 * E * I) + Nf * Nf * L / (2 * E * A);
      CHECK(0.5 * e.dot(S * e) == Approx(U_exact).epsilon(1e-6));
      // (c) statics: D^T S e on (xp, phi_p, xq, phi_q).
      Eigen::Matrix<Ad, 6, 1> z;
      const Eigen::Matrix<double, 6, 1> z0 =
          (Eigen::Matrix<double, 6, 1>() << xp, php, xq, phq).finished();
      for (int i = 0; i < 6; ++i) z(i) = Ad(z0(i), 6, i);
      const Vec2<Ad> xpa = z.segment<2>(0), xqa = z.segment<2>(3);
      const auto ea = planar_beam_deformations<Ad>(xpa, z(2), xqa, z(5), ref);
      Eigen::Matrix<double, 3, 6> J;
      for (int k = 0; k < 3; ++k) J.row(k) = ea(k).derivatives().transpose();
      const Eigen::Matrix<double, 6, 1> g = J.transpose() * (S * e);
      const Eigen::Vector2d F = Nf * ex + Pf * ey;
      const double fs = std::max(Pf, Nf);
      CHECK((g.segment<2>(3) - F).norm() <= 1e-5 * fs);      // applied tip force
      CHECK(std::abs(g(5)) <= 1e-5 * fs * L);                // free tip: no moment
      CHECK((g.segment<2>(0) + F).norm() <= 1e-5 * fs);      // reaction force
      CHECK(g(2) == Approx(-L * Pf).margin(1e-5 * fs * L));  // reaction moment -(L ex x F)_z
    }
  }
  CHECK_THROWS_AS(planar_beam_stiffness(E, A, I, -1.0), std::invalid_argument);
}
