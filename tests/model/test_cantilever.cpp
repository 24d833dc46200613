// SPDX-License-Identifier: BSD-3-Clause
// doc/design.md §3 validation case 2: a clamped-free Euler-Bernoulli beam. Its bending frequencies
//   omega_i = (beta_i L)^2 sqrt(EI / (rho A L^4)),  beta L = 1.8751, 4.6941, 7.8548
// are approached by n planar beams (2-D) and n spatial beams (3-D, both bending planes).
//
// Model. Nodes 0..n on the x axis, node 0 clamped (fixed_nodes), every other nodal coordinate
// dependent. The element mass rho A l is lumped, rho A l / 2 on each end node, on the
// translations only: the nodal rotations carry no inertia, so the bending deformations span
// massless directions and are condensed out exactly (massless_condensation.hpp). The axial
// elongation e1 of every element is declared rigid: the axial modes are far above the first
// bending modes and, being rigid, e1 neither adds states nor couples (the axial inertia of a
// straight beam does not enter the transverse dynamics to first order). The dynamic
// coordinates are the flexible deformations: e2, e3 of each planar beam; e2 (torsion) .. e6 of
// each spatial beam.
//
// Besides the continuum frequencies, each discrete frequency is compared with the same
// discretisation assembled by hand in this file (Hermite beam stiffness, lumped masses,
// rotations condensed): textbook_hz, which pins the engine and the condensation down to rounding.
// The measured errors and the bounds (observations with a margin) are listed at kBound.
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <string>

#include "numeric/constants.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/massless_condensation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop::plant;

namespace {

constexpr double kL = 1.2;        // m
constexpr double kE = 2.1e11;     // Pa
constexpr double kG = 8.1e10;     // Pa
constexpr double kRho = 7850.0;   // kg/m^3
constexpr double kA = 4.0e-4;     // m^2 (20 mm x 20 mm)
constexpr double kI = 1.3333e-8;  // m^4
constexpr double kJ = 2.25e-8;    // m^4
constexpr double kBetaL[3] = {1.8751, 4.6941, 7.8548};
using flexloop::numeric::kPi;

double euler_bernoulli_hz(int mode, double I) {
  const double bl = kBetaL[mode];
  return bl * bl * std::sqrt(kE * I / (kRho * kA * std::pow(kL, 4))) / (2.0 * kPi);
}

std::string planar_cantilever(int n) {
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"cantilever2d\"\ndimension = 2\n";
  for (int i = 0; i <= n; ++i)
    os << "[[node]]\nid = \"" << i << "\"\nposition = [" << kL * i / n
       << ", 0.0]\nrotational = true\n";
  for (int k = 1; k <= n; ++k)
    os << "[[element]]\nid = \"b" << k << "\"\ntype = \"planar_beam\"\nnodes = [\"" << k - 1
       << "\", \"" << k << "\"]\nE = " << kE << "\nA = " << kA << "\nI = " << kI
       << "\nrho = " << kRho << "\nmodes = [\"rigid\", \"flexible\", \"flexible\"]\n";
  os << "[coordinates]\nfixed_nodes = [\"0\"]\ndynamic = [";
  for (int k = 1; k <= n; ++k)
    os << (k > 1 ? ", " : "") << "\"e2.b" << k << "\", \"e3.b" << k << "\"";
  os << "]\n";
  return os.str();
}

std::string spatial_cantilever(int n, double Iy, double Iz) {
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"cantilever3d\"\ndimension = 3\n";
  for (int i = 0; i <= n; ++i)
    os << "[[node]]\nid = \"" << i << "\"\nposition = [" << kL * i / n
       << ", 0.0, 0.0]\nrotational = true\n";
  for (int k = 1; k <= n; ++k)
    os << "[[element]]\nid = \"b" << k << "\"\ntype = \"beam\"\nnodes = [\"" << k - 1 << "\", \""
       << k << "\"]\nE = " << kE << "\nG = " << kG << "\nA = " << kA << "\nIy = " << Iy
       << "\nIz = " << Iz << "\nJ = " << kJ << "\nrho = " << kRho
       << "\ny_axis = [0.0, 1.0, 0.0]\n"
          "modes = [\"rigid\", \"flexible\", \"flexible\", \"flexible\", \"flexible\", "
          "\"flexible\"]\n";
  os << "[coordinates]\nfixed_nodes = [\"0\"]\ndynamic = [";
  for (int k = 1; k <= n; ++k)
    for (int d = 2; d <= 6; ++d) os << (k + d > 3 ? ", " : "") << "\"e" << d << ".b" << k << "\"";
  os << "]\n";
  return os.str();
}

struct Reduced {
  model::MasslessCondensation c;
  lti::Modes modes;
};

Reduced reduced_modes(const std::string& text, const std::string& name) {
  const auto m = model::parse_model(text, name);
  const auto lin = model::linearise(m);
  Reduced r{model::condense_massless(m, lin), {}};
  r.modes = lti::natural_modes(r.c.M, r.c.K + r.c.G);
  return r;
}

// Independent textbook model (not the code under test): Hermite-cubic beam stiffness on the
// nodal (v, theta), lumped masses rho A l (interior) and rho A l / 2 (tip) on v, the rotations
// condensed by hand (Schur complement); frequencies in Hz, ascending.
Eigen::VectorXd textbook_hz(int n, double I) {
  const double l = kL / n, c = kE * I / (l * l * l);
  const int N = 2 * n;  // (v_i, theta_i), i = 1..n; node 0 clamped
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(N + 2, N + 2);
  Eigen::Matrix4d ke;
  ke << 12, 6 * l, -12, 6 * l, 6 * l, 4 * l * l, -6 * l, 2 * l * l, -12, -6 * l, 12, -6 * l, 6 * l,
      2 * l * l, -6 * l, 4 * l * l;
  for (int k = 0; k < n; ++k) K.block<4, 4>(2 * k, 2 * k) += c * ke;
  Eigen::MatrixXd Kvv(n, n), Kvt(n, n), Ktt(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Kvv(i, j) = K(2 * i + 2, 2 * j + 2);
      Kvt(i, j) = K(2 * i + 2, 2 * j + 3);
      Ktt(i, j) = K(2 * i + 3, 2 * j + 3);
    }
  const Eigen::MatrixXd Kr = Kvv - Kvt * Ktt.ldlt().solve(Kvt.transpose());
  Eigen::VectorXd mass = Eigen::VectorXd::Constant(n, kRho * kA * l);
  mass(n - 1) *= 0.5;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Kr,
                                                               Eigen::MatrixXd(mass.asDiagonal()));
  return es.eigenvalues().cwiseSqrt() / (2.0 * kPi);
}

// Measured relative errors (f - f_EB) / f_EB, identical in 2-D and 3-D (and to the textbook
// model); all negative (lumped masses lower the frequencies), O(1/n^2):
//   n     mode 1      mode 2      mode 3
//   5     -1.80e-2    -5.90e-2    -9.31e-2
//   10    -4.56e-3    -1.56e-2    -2.55e-2
//   20    -1.14e-3    -3.97e-3    -6.51e-3
//   40    -2.82e-4    -9.99e-4    -1.64e-3
constexpr int kCounts[4] = {5, 10, 20, 40};
constexpr double kBound[4][3] = {{0.025, 0.07, 0.11},  // observed with ~20-50% margin
                                 {0.006, 0.02, 0.032},
                                 {0.0015, 0.005, 0.008},
                                 {4e-4, 1.3e-3, 2.1e-3}};

// The checks shared by 2-D and 3-D for the frequencies f of the bending modes in one plane.
void check_convergence(int step, const Eigen::VectorXd& f, double I,
                       const Eigen::VectorXd& textbook, double previous[3]) {
  for (int i = 0; i < 3; ++i) {
    const double exact = euler_bernoulli_hz(i, I);
    const double err = (f(i) - exact) / exact;
    WARN("n=" << kCounts[step] << " mode " << i + 1 << ": " << f(i) << " Hz, Euler-Bernoulli "
              << exact << " Hz, rel.err " << err);
    CHECK(std::abs(f(i) - textbook(i)) <= 1e-8 * textbook(i));
    CHECK(err < 0.0);
    CHECK(-err < kBound[step][i]);
    if (step > 0) {  // halving the element length divides the error by about 4
      CHECK(previous[i] / err > 3.5);
      CHECK(previous[i] / err < 4.5);
    }
    previous[i] = err;
  }
  if (kCounts[step] == 40)
    CHECK(std::abs(f(0) - euler_bernoulli_hz(0, I)) < 0.005 * euler_bernoulli_hz(0, I));
}

}  // namespace

TEST_CASE("cantilever 2-D: bending frequencies converge to Euler-Bernoulli") {
  double previous[3] = {};
  for (int step = 0; step < 4; ++step) {
    const int n = kCounts[step];
    const auto r = reduced_modes(planar_cantilever(n), "cantilever2d.toml");
    // One massive direction per free node (its transverse translation); rotations condensed.
    REQUIRE(r.c.massless_count == n);
    REQUIRE(r.modes.frequencies_hz.size() == n);
    CHECK(r.c.damping_coupling == 0.0);
    check_convergence(step, r.modes.frequencies_hz, kI, textbook_hz(n, kI), previous);
  }
}

TEST_CASE(
    "cantilever 3-D: both bending planes converge to Euler-Bernoulli and agree when Iy = Iz") {
  double previous_a[3] = {}, previous_b[3] = {};
  for (int step = 0; step < 4; ++step) {
    const int n = kCounts[step];
    const auto r = reduced_modes(spatial_cantilever(n, kI, kI), "cantilever3d.toml");
    // Two massive directions per free node (the two transverse translations); the three
    // rotations (torsion and both bendings) per node are condensed.
    REQUIRE(r.c.massless_count == 3 * n);
    REQUIRE(r.modes.frequencies_hz.size() == 2 * n);
    const Eigen::VectorXd& f = r.modes.frequencies_hz;
    Eigen::VectorXd fa(3), fb(3);
    for (int i = 0; i < 3; ++i) {
      fa(i) = f(2 * i), fb(i) = f(2 * i + 1);
      CHECK(std::abs(fa(i) - fb(i)) <= 1e-9 * fa(i));  // the two planes, pairwise equal
    }
    const Eigen::VectorXd textbook = textbook_hz(n, kI);
    check_convergence(step, fa, kI, textbook, previous_a);
    check_convergence(step, fb, kI, textbook, previous_b);
  }
}

TEST_CASE("cantilever 3-D: Iy governs bending in the x-z plane, Iz in the x-y plane") {
  // Iy = 4 Iz: the x-y modes (about z) come first, the x-z modes at exactly twice their
  // frequency (same masses, stiffness scaled by 4). The lowest mode moves the tip along y.
  const int n = 10;
  const double Iz = kI, Iy = 4.0 * kI;
  const auto m = model::parse_model(spatial_cantilever(n, Iy, Iz), "cantilever3d.toml");
  const auto lin = model::linearise(m);
  const auto c = model::condense_massless(m, lin);
  const auto modes = lti::natural_modes(c.M, c.K + c.G);
  const Eigen::VectorXd xy = textbook_hz(n, Iz), xz = textbook_hz(n, Iy);
  CHECK(std::abs(modes.frequencies_hz(0) - xy(0)) <= 1e-8 * xy(0));
  CHECK(std::abs(modes.frequencies_hz(1) - xz(0)) <= 1e-8 * xz(0));
  CHECK(std::abs(modes.frequencies_hz(1) / modes.frequencies_hz(0) - 2.0) <= 1e-9);
  // Mode shape of the first mode in nodal coordinates: x = DF(x) q_d, q_d = T a.
  const Eigen::VectorXd qd = c.T * modes.shapes.col(0);
  const Eigen::VectorXd dx = lin.DFx.leftCols(m.nd()) * qd;
  const double tip_y = dx(m.coordinate_index("y." + std::to_string(n)));
  const double tip_z = dx(m.coordinate_index("z." + std::to_string(n)));
  CHECK(std::abs(tip_y) > 0.0);
  CHECK(std::abs(tip_z) <= 1e-9 * std::abs(tip_y));
}

TEST_CASE("massless condensation: springs in series, a massless mechanism, damping policy") {
  // Mass m on spring k1 to ground and, through a massless node, on k2 then k3 to ground:
  // the reduced stiffness is k1 + k2 k3 / (k2 + k3) (series springs).
  const double m = 2.0, k1 = 100.0, k2 = 300.0, k3 = 600.0;
  Eigen::MatrixXd M(2, 2), K(2, 2), D(2, 2);
  M << m, 0, 0, 0;
  K << k1 + k2, -k2, -k2, k2 + k3;
  const auto c = model::condense_massless(M, K, {}, {});
  REQUIRE(c.massless_count == 1);
  CHECK(std::abs(c.M(0, 0) - m) <= 1e-14 * m);
  CHECK(std::abs(c.K(0, 0) / (c.T(0, 0) * c.T(0, 0)) - (k1 + k2 * k3 / (k2 + k3))) <= 1e-12 * k1);
  CHECK(std::abs(c.T(1, 0) / c.T(0, 0) - k2 / (k2 + k3)) <= 1e-14);  // the massless node follows

  // Damping only on the massive coordinate: exact, coupling 0. Damping on the massless node:
  // projected by default, refused on request.
  D << 5.0, 0, 0, 0;
  CHECK(model::condense_massless(M, K, D, {}).damping_coupling == 0.0);
  D << 0, 0, 0, 5.0;
  const auto projected = model::condense_massless(M, K, D, {});
  CHECK(projected.damping_coupling == Approx(1.0));
  CHECK(projected.D(0, 0) / (projected.T(0, 0) * projected.T(0, 0)) ==
        Approx(5.0 * std::pow(k2 / (k2 + k3), 2)));
  model::CondensationOptions refuse;
  refuse.damping = model::MasslessDampingPolicy::kRefuse;
  CHECK_THROWS_WITH(model::condense_massless(M, K, D, {}, refuse),
                    Catch::Contains("damping acts on massless directions"));

  // A massless coordinate without stiffness: a mechanism, named in the message.
  K << k1, 0, 0, 0;
  CHECK_THROWS_AS(model::condense_massless(M, K, {}, {}, {}, {"x.mass", "x.free"}),
                  std::invalid_argument);
  CHECK_THROWS_WITH(model::condense_massless(M, K, {}, {}, {}, {"x.mass", "x.free"}),
                    Catch::Contains("massless mechanism") && Catch::Contains("x.free"));
}
