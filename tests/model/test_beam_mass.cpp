// SPDX-License-Identifier: BSD-3-Clause
// Issue 17, case 4: beam elements with a consistent mass that includes rotary inertia
// (mass_model = "beam", plant/model/beam_mass.hpp).
//
// References nobody here computed with the code under test:
// - Przemieniecki, Theory of Matrix Structural Analysis (1968), §11: the frame element's
//   consistent mass in its own axes, assembled below from the textbook blocks (axial
//   m/6 [2 1; 1 2], bending m/420 [156 22l 54 -13l; ...], rotary inertia rho I/(30 l)
//   [36 3l -36 3l; ...], torsion rho I_p l/6 [2 1; 1 2]) and turned into the model's axes;
// - the Rayleigh beam (bending with rotary inertia), simply supported: exactly
//     omega_k^2 = (EI / rho A) (k pi / L)^4 / (1 + (I / A) (k pi / L)^2);
// - uniform torsion of a clamped-free shaft: omega_k = (2k - 1) pi / (2 L) sqrt(G J / (rho I_p)).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/model/beam_mass.hpp"
#include "plant/model/inertia.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/massless_condensation.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/model/rotation.hpp"

using namespace flexloop::plant;

namespace {

using flexloop::numeric::kPi;
constexpr double kE = 2.1e11, kG = 8.1e10, kRho = 7850.0;

// Textbook blocks over (w_p, theta_p, w_q, theta_q) of a beam of length l.
Eigen::Matrix4d bending_translation(double mass, double l) {
  Eigen::Matrix4d M;
  M << 156, 22 * l, 54, -13 * l,  //
      22 * l, 4 * l * l, 13 * l, -3 * l * l, 54, 13 * l, 156, -22 * l, -13 * l, -3 * l * l, -22 * l,
      4 * l * l;
  return mass / 420 * M;
}
Eigen::Matrix4d bending_rotary(double rho_I, double l) {
  Eigen::Matrix4d M;
  M << 36, 3 * l, -36, 3 * l,  //
      3 * l, 4 * l * l, -3 * l, -l * l, -36, -3 * l, 36, -3 * l, 3 * l, -l * l, -3 * l, 4 * l * l;
  return rho_I / (30 * l) * M;
}
Eigen::Matrix2d axial(double mass) {
  return mass / 6 * (Eigen::Matrix2d() << 2, 1, 1, 2).finished();
}

void add(Eigen::MatrixXd& M, const Eigen::MatrixXd& block, const std::vector<int>& at) {
  for (std::size_t i = 0; i < at.size(); ++i)
    for (std::size_t j = 0; j < at.size(); ++j)
      M(at[i], at[j]) += block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace

TEST_CASE("beam mass: a planar element is Przemieniecki's consistent mass with rotary inertia",
          "[model][beam_mass]") {
  const double l = 0.35, angle = 0.4, A = 4e-4, I = 2e-7, m = kRho * A * l;
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"one_beam\"\ndimension = 2\n"
     << "[[node]]\nid = \"p\"\nposition = [0.1, -0.2]\nangle = 0.3\n"
     << "[[node]]\nid = \"q\"\nposition = [" << 0.1 + l * std::cos(angle) << ", "
     << -0.2 + l * std::sin(angle) << "]\nangle = -0.7\n"
     << "[[element]]\nid = \"b\"\ntype = \"planar_beam\"\nnodes = [\"p\", \"q\"]\nE = " << kE
     << "\nA = " << A << "\nI = " << I << "\nrho = " << kRho << "\nmass_model = \"beam\"\n"
     << "[coordinates]\nfixed_nodes = [\"p\"]\ndynamic = [\"x.q\", \"y.q\", \"phi.q\"]\n";
  const model::Model model = model::parse_model(os.str(), "one_beam.toml");
  const Eigen::MatrixXd M = model::beam_element_mass(model, model.elements[0], model.x_reference);
  // Local axes (u along the beam, w across, theta) from the model's (x, y, phi).
  Eigen::MatrixXd local = Eigen::MatrixXd::Zero(6, 6);
  add(local, axial(m), {0, 3});
  add(local, bending_translation(m, l) + bending_rotary(kRho * I, l), {1, 2, 4, 5});
  Eigen::MatrixXd turn = Eigen::MatrixXd::Identity(6, 6);
  for (int node : {0, 3})
    turn.block(node, node, 2, 2) << std::cos(angle), std::sin(angle), -std::sin(angle),
        std::cos(angle);
  CHECK(relative_difference(M, turn.transpose() * local * turn) <= 1e-14);
  // The whole model's mass matrix carries it on the nodes' coordinates (no other mass).
  CHECK(relative_difference(model::mass_matrix(model, model.x_reference), M) <= 1e-15);
}

TEST_CASE("beam mass: a spatial element is the 12 x 12 frame element's, over Euler parameters",
          "[model][beam_mass]") {
  const double l = 0.6, A = 3e-4, Iy = 5e-8, Iz = 2e-8, m = kRho * A * l;
  const Eigen::Vector3d xp(0.2, -0.1, 0.3), axis = Eigen::Vector3d(1, 2, 2) / 3.0;
  const Eigen::Vector3d xq = xp + l * axis;
  const Eigen::Vector4d lp = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized(),
                        lq = Eigen::Vector4d(0.5, -0.4, 0.6, 0.3).normalized();
  const auto vec = [](const Eigen::VectorXd& v) {
    std::ostringstream s;
    s.precision(17);
    s << "[" << v(0);
    for (Eigen::Index i = 1; i < v.size(); ++i) s << ", " << v(i);
    s << "]";
    return s.str();
  };
  std::ostringstream os;
  os << "[model]\nname = \"one_beam\"\ndimension = 3\n"
     << "[[node]]\nid = \"p\"\nposition = " << vec(xp) << "\norientation = " << vec(lp) << "\n"
     << "[[node]]\nid = \"q\"\nposition = " << vec(xq) << "\norientation = " << vec(lq) << "\n"
     << "[[element]]\nid = \"b\"\ntype = \"beam\"\nnodes = [\"p\", \"q\"]\nE = " << kE
     << "\nG = " << kG << "\nA = " << A << "\nIy = " << Iy << "\nIz = " << Iz
     << "\nJ = 1e-8\nrho = " << kRho << "\ny_axis = [0.0, 0.0, 1.0]\nmass_model = \"beam\"\n"
     << "[coordinates]\nfixed_nodes = [\"p\"]\n"
     << "dynamic = [\"x.q\", \"y.q\", \"z.q\", \"l1.q\", \"l2.q\", \"l3.q\"]\n";
  const model::Model model = model::parse_model(os.str(), "one_beam.toml");
  const Eigen::MatrixXd M = model::beam_element_mass(model, model.elements[0], model.x_reference);
  REQUIRE(M.rows() == 14);
  // The beam's axes as flexloop defines them: x along it, y the hint made normal to it.
  const Eigen::Vector3d ex = axis, ey = (Eigen::Vector3d::UnitZ() - axis.z() * axis).normalized(),
                        ez = ex.cross(ey);
  Eigen::Matrix3d Q;
  Q << ex.transpose(), ey.transpose(), ez.transpose();
  // Velocities and angular velocities (global) to coordinate rates: lambda' = L^T R^T w / 2.
  Eigen::MatrixXd rates = Eigen::MatrixXd::Zero(14, 12);
  for (int node = 0; node < 2; ++node) {
    const Eigen::Vector4d& lambda = node == 0 ? lp : lq;
    rates.block(7 * node, 6 * node, 3, 3).setIdentity();
    rates.block(7 * node + 3, 6 * node + 3, 4, 3) =
        0.5 * model::euler_l_matrix(lambda).transpose() *
        model::rotation_matrix<double>(lambda).transpose();
  }
  // Local (u, v, w, theta_x, theta_y, theta_z) per node; w' = -theta_y in the x-z plane.
  Eigen::MatrixXd local = Eigen::MatrixXd::Zero(12, 12);
  add(local, axial(m), {0, 6});
  add(local, axial(kRho * (Iy + Iz) * l), {3, 9});  // rho I_p l / 6 [2 1; 1 2]
  add(local, bending_translation(m, l) + bending_rotary(kRho * Iz, l), {1, 5, 7, 11});
  const Eigen::Matrix4d flip = Eigen::Vector4d(1, -1, 1, -1).asDiagonal();
  add(local, flip * (bending_translation(m, l) + bending_rotary(kRho * Iy, l)) * flip,
      {2, 4, 8, 10});
  Eigen::MatrixXd turn = Eigen::MatrixXd::Zero(12, 12);
  for (int b = 0; b < 4; ++b) turn.block(3 * b, 3 * b, 3, 3) = Q;
  CHECK(relative_difference(rates.transpose() * M * rates, turn.transpose() * local * turn) <=
        1e-13);
}

namespace {

// A simply supported planar beam of n elements: pinned at node 0, on a roller at node n (e1
// rigid: no axial modes), the bending deformations dynamic.
std::string supported_beam(int n, double L, double A, double I, const std::string& mass_model) {
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"supported\"\ndimension = 2\n";
  for (int i = 0; i <= n; ++i)
    os << "[[node]]\nid = \"" << i << "\"\nposition = [" << L * i / n
       << ", 0.0]\nrotational = true\n";
  for (int k = 1; k <= n; ++k)
    os << "[[element]]\nid = \"b" << k << "\"\ntype = \"planar_beam\"\nnodes = [\"" << k - 1
       << "\", \"" << k << "\"]\nE = " << kE << "\nA = " << A << "\nI = " << I << "\nrho = " << kRho
       << "\nmass_model = \"" << mass_model
       << "\"\nmodes = [\"rigid\", \"flexible\", \"flexible\"]\n";
  os << "[coordinates]\nfixed = [\"x.0\", \"y.0\", \"y." << n << "\"]\ndynamic = [";
  for (int k = 1; k <= n; ++k)
    os << (k > 1 ? ", " : "") << "\"e2.b" << k << "\", \"e3.b" << k << "\"";
  os << "]\n";
  return os.str();
}

Eigen::VectorXd frequencies_hz(const std::string& text) {
  const auto m = model::parse_model(text, "beam.toml");
  const auto lin = model::linearise(m);
  const auto c = model::condense_massless(m, lin);
  return lti::natural_modes(c.M, c.K + c.G).frequencies_hz;
}

}  // namespace

TEST_CASE(
    "beam mass: a stocky simply supported beam converges to the Rayleigh beam as 1/n^4, from "
    "above",
    "[model][beam_mass]") {
  // r / L = 0.05: rotary inertia lowers the first mode by 1.2 %, the third by 10 %.
  const double L = 1.2, A = 4e-4, r = 0.05 * L, I = A * r * r;
  const auto rayleigh_hz = [&](int k) {
    const double kl = k * kPi / L;
    return kl * kl * std::sqrt(kE * I / (kRho * A)) / std::sqrt(1 + I / A * kl * kl) / (2 * kPi);
  };
  const auto euler_bernoulli_hz = [&](int k) {
    const double kl = k * kPi / L;
    return kl * kl * std::sqrt(kE * I / (kRho * A)) / (2 * kPi);
  };
  // Measured (f - f_Rayleigh) / f_Rayleigh, modes 1..3: n = 4: 2.6e-4, 3.9e-3, 1.8e-2;
  // n = 8: 1.6e-5, 2.6e-4, 1.3e-3; n = 16: 1.0e-6, 1.6e-5, 8.3e-5 (falling by 14-16 per halving).
  // Bounds at n = 16: 1.5e-4 k^4 / 81, about 1.8 times the measured errors.
  double previous[3] = {};
  for (const int n : {4, 8, 16}) {
    const Eigen::VectorXd f = frequencies_hz(supported_beam(n, L, A, I, "beam"));
    REQUIRE(f.size() == 2 * n);  // nothing massless: every rotation carries inertia
    for (int k = 1; k <= 3; ++k) {
      const double exact = rayleigh_hz(k), err = (f(k - 1) - exact) / exact;
      WARN("n = " << n << " mode " << k << ": " << f(k - 1) << " Hz, Rayleigh beam " << exact
                  << " Hz, Euler-Bernoulli " << euler_bernoulli_hz(k) << " Hz, rel. error " << err);
      CHECK(err > 0);  // Rayleigh-Ritz: from above
      if (n == 16) CHECK(err <= 1.5e-4 * std::pow(k, 4) / 81);
      if (previous[k - 1] > 0) CHECK(previous[k - 1] / err >= 12);  // order 4: 16 per halving
      previous[k - 1] = err;
    }
  }
  // What the rotary inertia is worth: lumped masses (none) converge to Euler-Bernoulli instead.
  const Eigen::VectorXd lumped = frequencies_hz(supported_beam(64, L, A, I, "lumped"));
  CHECK(std::abs(lumped(0) / euler_bernoulli_hz(1) - 1) <= 1e-3);
  CHECK(euler_bernoulli_hz(1) / rayleigh_hz(1) - 1 >= 0.01);
}

TEST_CASE("beam mass: a spatial shaft's torsion converges to the exact frequencies, from above",
          "[model][beam_mass]") {
  const double L = 1.0, A = 4e-4, Iy = 1.5e-8, Iz = 1.2e-8, J = 2.2e-8;
  const auto torsion_hz = [&](int k) {
    return (2 * k - 1) * kPi / (2 * L) * std::sqrt(kG * J / (kRho * (Iy + Iz))) / (2 * kPi);
  };
  double previous = 0;
  for (const int n : {4, 8, 16}) {
    std::ostringstream os;
    os.precision(17);
    os << "[model]\nname = \"shaft\"\ndimension = 3\n";
    for (int i = 0; i <= n; ++i)
      os << "[[node]]\nid = \"" << i << "\"\nposition = [0.0, " << L * i / n
         << ", 0.0]\nrotational = true\n";
    for (int k = 1; k <= n; ++k)
      os << "[[element]]\nid = \"b" << k << "\"\ntype = \"beam\"\nnodes = [\"" << k - 1 << "\", \""
         << k << "\"]\nE = " << kE << "\nG = " << kG << "\nA = " << A << "\nIy = " << Iy
         << "\nIz = " << Iz << "\nJ = " << J << "\nrho = " << kRho
         << "\nmass_model = \"beam\"\nmodes = [\"rigid\", \"flexible\", \"flexible\", "
            "\"flexible\", \"flexible\", \"flexible\"]\n";
    os << "[coordinates]\nfixed_nodes = [\"0\"]\ndynamic = [";
    for (int k = 1; k <= n; ++k)
      for (int d = 2; d <= 6; ++d) os << (k + d > 3 ? ", " : "") << "\"e" << d << ".b" << k << "\"";
    os << "]\n";
    const auto m = model::parse_model(os.str(), "shaft.toml");
    const auto lin = model::linearise(m);
    const auto c = model::condense_massless(m, lin);
    REQUIRE(c.massless_count == 0);
    const lti::Modes modes = lti::natural_modes(c.M, c.K + c.G);
    // The torsional modes: shapes in the twist deformations e2 alone (a straight shaft does not
    // couple twist and bending).
    std::vector<double> torsion;
    for (Eigen::Index i = 0; i < modes.shapes.cols(); ++i) {
      const Eigen::VectorXd qd = c.T * modes.shapes.col(i);
      double twist = 0;
      for (int k = 1; k <= n; ++k) twist += std::pow(qd(5 * (k - 1)), 2);  // e2.bk (listed first)
      if (twist >= 0.99 * qd.squaredNorm()) torsion.push_back(modes.frequencies_hz(i));
    }
    REQUIRE(torsion.size() == static_cast<std::size_t>(n));
    const double err = (torsion[0] - torsion_hz(1)) / torsion_hz(1);
    WARN("n = " << n << ": first torsion " << torsion[0] << " Hz, exact " << torsion_hz(1)
                << " Hz, rel. error " << err);
    CHECK(err > 0);
    if (previous > 0) CHECK(previous / err >= 3.5);  // order 2: 4 per halving
    previous = err;
  }
}

TEST_CASE("beam mass: refused on a truss, and at an operating point that moves",
          "[model][beam_mass]") {
  const std::string nodes =
      "[model]\nname = \"m\"\ndimension = 2\n[[node]]\nid = \"p\"\nposition = [0.0, 0.0]\n"
      "rotational = true\n[[node]]\nid = \"q\"\nposition = [1.0, 0.0]\nrotational = true\n";
  const std::string truss = nodes +
                            "[[element]]\nid = \"t\"\ntype = \"truss\"\nnodes = [\"p\", \"q\"]\n"
                            "stiffness = 1e6\nmass = 1.0\nmass_model = \"beam\"\n"
                            "[coordinates]\nfixed_nodes = [\"p\"]\ndynamic = [\"x.q\"]\n";
  CHECK_THROWS_WITH(
      model::parse_model(truss, "truss.toml"),
      Catch::Contains("truss.toml:") && Catch::Contains("the mass of a beam element"));
  const std::string beam = nodes +
                           "[[element]]\nid = \"b\"\ntype = \"planar_beam\"\nnodes = [\"p\", "
                           "\"q\"]\nE = 2e11\nA = 1e-4\nI = 1e-9\nrho = 7850\nmass_model = "
                           "\"beam\"\n[coordinates]\nfixed_nodes = [\"p\"]\n"
                           "dynamic = [\"x.q\", \"y.q\", \"phi.q\"]\n";
  const model::Model m = model::parse_model(beam, "beam.toml");
  CHECK_NOTHROW(model::linearise(m));  // at rest
  model::OperatingPoint moving;
  moving.qd = Eigen::VectorXd::Unit(3, 1);
  CHECK_THROWS_AS(model::linearise(m, moving), flexloop::common::InputError);
  CHECK_THROWS_WITH(model::linearise(m, moving),
                    Catch::Contains("beam.toml:") && Catch::Contains("linearised at rest only"));
}
