// SPDX-License-Identifier: BSD-3-Clause
// Issue 17, case 4: a beam model with lumped translational masses and no nodal rotary inertia
// goes through the state-space builder (flexloop linearise and analyse), its massless bending
// directions condensed statically (plant/lti/state_space_builder.hpp).
//
// References nobody here computed with the code under test:
// - Euler-Bernoulli clamped-free bending frequencies
//     omega_i = (beta_i L)^2 sqrt(EI / (rho A L^4)),  beta L = 1.8751, 4.6941, 7.8548;
//   this lumped-mass discretisation (no rotary inertia) approaches them from below, the error
//   falling as 1/n^2 (measured below; the same numbers as tests/model/test_cantilever.cpp, which
//   condenses the same discretisation outside the state space);
// - static deflection and rotation of a cantilever: tip force P: v = P L^3 / (3 EI),
//   theta = P L^2 / (2 EI); tip moment Q: v = Q L^2 / (2 EI), theta = Q L / (EI) (Hermite-cubic
//   beams are nodally exact for end loads);
// - a rigid motion of the clamp carries the beam along: DC gain 1 (translation), L (rotation to
//   tip deflection);
// - the same model with a small nodal rotary inertia epsilon (not condensed) tends to the
//   condensed one as epsilon -> 0.
// Two parametrisations of one discretisation: the bending deformations e2, e3 as dynamic
// coordinates (mass from rho, the massless directions are combinations of all coordinates), and
// the nodal y, phi (nodal masses; the massless directions are exactly the rotations phi).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop::plant;

namespace {

constexpr double kL = 1.2;        // m
constexpr double kE = 2.1e11;     // Pa
constexpr double kRho = 7850.0;   // kg/m^3
constexpr double kA = 4.0e-4;     // m^2
constexpr double kI = 1.3333e-8;  // m^4
constexpr double kBetaL[3] = {1.8751, 4.6941, 7.8548};
using flexloop::numeric::kPi;

double euler_bernoulli_hz(int mode) {
  const double bl = kBetaL[mode];
  return bl * bl * std::sqrt(kE * kI / (kRho * kA * std::pow(kL, 4))) / (2.0 * kPi);
}

enum class Coordinates { kDeformations, kNodal };

struct Options {
  Coordinates coords = Coordinates::kDeformations;
  double rotary_inertia = 0.0;   // per free node, kg m^2 (nodal model only)
  double bending_damping = 0.0;  // on e2, e3 of every element
  std::string tip_release;       // "released": the last element's e3 is a hinge
  bool prescribed_base = false;  // nodal model: y.0 and phi.0 prescribed instead of fixed
};

Options opts(Coordinates c) {
  Options o;
  o.coords = c;
  return o;
}

// n planar beams on the x axis, node 0 clamped. Deformations model: the element mass rho A l
// lumped on the end translations. Nodal model: the same masses given as nodal masses
// (rho A l inside, rho A l / 2 at the tip; half of the first element's mass sits on the clamp).
std::string cantilever(int n, const Options& o) {
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"lumped_cantilever\"\ndimension = 2\n";
  const double l = kL / n, ml = kRho * kA * l;
  for (int i = 0; i <= n; ++i) {
    os << "[[node]]\nid = \"" << i << "\"\nposition = [" << l * i << ", 0.0]\nrotational = true\n";
    if (o.coords == Coordinates::kNodal && i > 0) {
      os << "mass = " << (i == n ? 0.5 * ml : ml) << "\n";
      if (o.rotary_inertia > 0.0) os << "inertia = " << o.rotary_inertia << "\n";
    }
  }
  for (int k = 1; k <= n; ++k) {
    os << "[[element]]\nid = \"b" << k << "\"\ntype = \"planar_beam\"\nnodes = [\"" << k - 1
       << "\", \"" << k << "\"]\nE = " << kE << "\nA = " << kA << "\nI = " << kI << "\n";
    if (o.coords == Coordinates::kDeformations) os << "rho = " << kRho << "\n";
    if (o.bending_damping > 0.0)
      os << "damping = [0.0, " << o.bending_damping << ", " << o.bending_damping << "]\n";
    const bool hinge = k == n && !o.tip_release.empty();
    os << "modes = [\"rigid\", \"flexible\", \"" << (hinge ? o.tip_release : "flexible") << "\"]\n";
  }
  os << "[coordinates]\n";
  if (o.prescribed_base)
    os << "fixed = [\"x.0\"]\nprescribed = [\"y.0\", \"phi.0\"]\n";
  else
    os << "fixed_nodes = [\"0\"]\n";
  os << "dynamic = [";
  for (int k = 1; k <= n; ++k) {
    if (o.coords == Coordinates::kDeformations)
      os << (k > 1 ? ", " : "") << "\"e2.b" << k << "\", \"e3.b" << k << "\"";
    else
      os << (k > 1 ? ", " : "") << "\"y." << k << "\", \"phi." << k << "\"";
  }
  os << "]\n";
  return os.str();
}

struct Built {
  model::Model m;
  model::Linearisation lin;
  lti::StateSpace ss;
  lti::Condensation c;
};

Built build(const std::string& text, const std::vector<std::string>& inputs,
            const std::vector<std::string>& outputs) {
  Built b{model::parse_model(text, "lumped_cantilever.toml"), {}, {}, {}};
  b.lin = model::linearise(b.m);
  b.ss = lti::build_state_space(b.m, b.lin, inputs, outputs, &b.c);
  return b;
}

// Undamped natural frequencies from the eigenvalues of A (+j omega of each pair), ascending, Hz.
std::vector<double> frequencies_hz(const Eigen::MatrixXd& A) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  std::vector<double> f;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
    if (es.eigenvalues()(i).imag() > 0.0) f.push_back(es.eigenvalues()(i).imag() / (2.0 * kPi));
  std::sort(f.begin(), f.end());
  return f;
}

Eigen::MatrixXd dc_gain(const lti::StateSpace& ss) {
  return ss.D - ss.C * ss.A.partialPivLu().solve(ss.B);
}

Eigen::MatrixXcd response(const lti::StateSpace& ss, double omega) {
  const Eigen::Index n = ss.nx();
  const Eigen::MatrixXcd sI = std::complex<double>(0.0, omega) * Eigen::MatrixXcd::Identity(n, n) -
                              ss.A.cast<std::complex<double>>();
  return ss.D.cast<std::complex<double>>() +
         ss.C.cast<std::complex<double>>() *
             sI.partialPivLu().solve(ss.B.cast<std::complex<double>>());
}

// Measured (f - f_EB) / f_EB through the state space (identical for both parametrisations):
//   n     mode 1      mode 2      mode 3
//   5     -1.80e-2    -5.90e-2    -9.31e-2
//   10    -4.56e-3    -1.56e-2    -2.55e-2
//   20    -1.14e-3    -3.97e-3    -6.51e-3
//   40    -2.82e-4    -9.99e-4    -1.64e-3
// Bounds: the observations with 20-50 % margin; below zero (lumped mass converges from below);
// the error divided by 3.5..4.5 per halving of the element length (O(1/n^2)).
constexpr int kCounts[4] = {5, 10, 20, 40};
constexpr double kBound[4][3] = {
    {0.025, 0.07, 0.11}, {0.006, 0.02, 0.032}, {0.0015, 0.005, 0.008}, {4e-4, 1.3e-3, 2.1e-3}};

}  // namespace

TEST_CASE(
    "lumped-mass cantilever: the state space condenses the massless bending directions and "
    "converges to Euler-Bernoulli",
    "[model][massless]") {
  for (const Coordinates coords : {Coordinates::kDeformations, Coordinates::kNodal}) {
    const bool nodal = coords == Coordinates::kNodal;
    double previous[3] = {};
    for (int step = 0; step < 4; ++step) {
      const int n = kCounts[step];
      const std::string tip = std::to_string(n);
      const Built b = build(cantilever(n, opts(coords)), {"force:y." + tip}, {"pos:y." + tip});
      INFO((nodal ? "nodal y, phi" : "deformations e2, e3") << ", n = " << n);
      // One massive direction per free node (its transverse translation): n states pairs.
      REQUIRE(b.c.massless_count == n);
      REQUIRE(b.ss.nx() == 2 * n);
      REQUIRE(b.c.state_coordinates.size() == static_cast<std::size_t>(n));
      REQUIRE(b.c.condensed.size() == static_cast<std::size_t>(n));
      CHECK(b.c.damping_coupling == 0.0);
      CHECK(b.c.rate_terms_dropped.empty());
      if (nodal)  // the massless directions are the rotations: the states are the translations
        for (int i = 1; i <= n; ++i) {
          CHECK(b.ss.states[static_cast<std::size_t>(i - 1)] == "pos:y." + std::to_string(i));
          CHECK(b.c.condensed[static_cast<std::size_t>(i - 1)] == "phi." + std::to_string(i));
        }
      const std::vector<double> f = frequencies_hz(b.ss.A);
      REQUIRE(f.size() == static_cast<std::size_t>(n));
      // Undamped: the eigenvalues of A are on the imaginary axis.
      CHECK(Eigen::EigenSolver<Eigen::MatrixXd>(b.ss.A, false)
                .eigenvalues()
                .real()
                .cwiseAbs()
                .maxCoeff() <= 1e-6 * f.back());
      for (int i = 0; i < 3; ++i) {
        const double exact = euler_bernoulli_hz(i);
        const double err = (f[static_cast<std::size_t>(i)] - exact) / exact;
        WARN((nodal ? "nodal" : "deformations")
             << " n=" << n << " mode " << i + 1 << ": " << f[static_cast<std::size_t>(i)]
             << " Hz, Euler-Bernoulli " << exact << " Hz, rel.err " << err);
        CHECK(err < 0.0);
        CHECK(-err < kBound[step][i]);
        if (step > 0) {
          CHECK(previous[i] / err > 3.5);
          CHECK(previous[i] / err < 4.5);
        }
        previous[i] = err;
      }
    }
  }
}

TEST_CASE(
    "lumped-mass cantilever: the DC gain of the condensed state space is the static "
    "deflection",
    "[model][massless]") {
  const double EI = kE * kI;
  for (const Coordinates coords : {Coordinates::kDeformations, Coordinates::kNodal}) {
    for (const int n : {1, 4, 10}) {
      const std::string tip = std::to_string(n);
      // Tip force (on a massive direction) and tip moment (on a massless direction: the static
      // feedthrough H g in D); tip deflection (massive) and rotation (massless: static map in C).
      const Built b = build(cantilever(n, opts(coords)), {"force:y." + tip, "force:phi." + tip},
                            {"pos:y." + tip, "pos:phi." + tip, "acc:y." + tip});
      INFO((coords == Coordinates::kNodal ? "nodal" : "deformations") << ", n = " << n);
      REQUIRE(b.c.massless_count == n);
      const Eigen::MatrixXd G = dc_gain(b.ss);
      WARN("n=" << n << " DC tip deflection/force " << G(0, 0) << " m/N, P L^3/(3EI) "
                << std::pow(kL, 3) / (3 * EI) << ", rel.err "
                << G(0, 0) / (std::pow(kL, 3) / (3 * EI)) - 1.0);
      CHECK(G(0, 0) == Approx(std::pow(kL, 3) / (3 * EI)).epsilon(1e-9));
      CHECK(G(1, 0) == Approx(kL * kL / (2 * EI)).epsilon(1e-9));
      CHECK(G(0, 1) == Approx(kL * kL / (2 * EI)).epsilon(1e-9));
      CHECK(G(1, 1) == Approx(kL / EI).epsilon(1e-9));
      // No static acceleration (against the high-frequency gain 1 / tip mass, 1/kg).
      CHECK(std::abs(G(2, 0)) <= 1e-9 / (0.5 * kRho * kA * kL / n));
      // The moment acts on massless directions: its rate is left out of q', q'' (named).
      CHECK(b.c.rate_terms_dropped == std::vector<std::string>{"force:phi." + tip});

      // The same numbers from the full static problem Kdd q = g, without any condensation.
      const int nd = b.m.nd();
      const Eigen::MatrixXd Kdd = b.lin.K.topLeftCorner(nd, nd);
      for (int j = 0; j < 2; ++j) {
        const int ci = b.m.coordinate_index(j == 0 ? "y." + tip : "phi." + tip);
        const Eigen::VectorXd g = b.lin.DFx.row(ci).head(nd).transpose();
        const Eigen::VectorXd q = Kdd.partialPivLu().solve(g);
        for (int o = 0; o < 2; ++o) {
          const int co = b.m.coordinate_index(o == 0 ? "y." + tip : "phi." + tip);
          const double full = b.lin.DFx.row(co).head(nd).dot(q);
          CHECK(std::abs(G(o, j) - full) <= 1e-10 * std::abs(full));
        }
      }
    }
  }
}

TEST_CASE("lumped-mass cantilever: condensed = the limit of a vanishing nodal rotary inertia",
          "[model][massless]") {
  // Nodal model, n = 6, with the clamp prescribed (y.0, phi.0 as position inputs: the massless
  // rotations follow the base through H g) and a tip force. The response at frequencies between
  // the modes agrees with the model whose free nodes carry a rotary inertia epsilon m l^2, to
  // O(epsilon) (measured: frequencies up to 1.17 epsilon, responses up to 10.8 epsilon apart).
  const int n = 6;
  const double l = kL / n, m = kRho * kA * l;
  Options o = opts(Coordinates::kNodal);
  o.prescribed_base = true;
  const std::vector<std::string> in{"force:y.6", "pos:y.0", "pos:phi.0"};
  const std::vector<std::string> out{"pos:y.6", "pos:phi.6", "pos:phi.3", "vel:y.6", "acc:y.6"};
  const Built c = build(cantilever(n, o), in, out);
  REQUIRE(c.c.massless_count == n);
  // Rigid motions of the clamp carry the beam along (static references).
  const Eigen::MatrixXd G0 = dc_gain(c.ss);
  CHECK(G0(0, 1) == Approx(1.0).epsilon(1e-9));  // tip y / base y
  CHECK(std::abs(G0(1, 1)) <= 1e-9);             // tip phi / base y
  CHECK(G0(0, 2) == Approx(kL).epsilon(1e-9));   // tip y / base phi
  CHECK(G0(1, 2) == Approx(1.0).epsilon(1e-9));  // tip phi / base phi
  CHECK(G0(2, 2) == Approx(1.0).epsilon(1e-9));  // mid phi / base phi
  // The prescribed positions reach the massless rotations; their rates have no signal here.
  CHECK(c.c.rate_terms_dropped == std::vector<std::string>{"pos:y.0", "pos:phi.0"});

  const std::vector<double> f = frequencies_hz(c.ss.A);
  for (const double eps : {1e-4, 1e-6}) {
    o.rotary_inertia = eps * m * l * l;
    const Built r = build(cantilever(n, o), in, out);
    REQUIRE(r.c.massless_count == 0);
    // Frequencies of the reference from the symmetric-definite eigenproblem (K, M): the
    // eigenvalues of its A, stiff from the tiny inertia, lose accuracy (1e-3 at epsilon 1e-6).
    const int nd = r.m.nd();
    const Eigen::VectorXd fr =
        lti::natural_modes(r.lin.M.topLeftCorner(nd, nd), r.lin.K.topLeftCorner(nd, nd))
            .frequencies_hz;
    // What the small inertia costs (reported, not checked): A is stiff (its norm grows as
    // 1 / epsilon) and the frequencies read from its eigenvalues lose accuracy.
    const std::vector<double> fa = frequencies_hz(r.ss.A);
    WARN("epsilon " << eps << ": ||A|| " << r.ss.A.norm() << " (condensed " << c.ss.A.norm()
                    << "); eigenvalues of A, modes 1-3, off by " << fa[0] / f[0] - 1.0 << ", "
                    << fa[1] / f[1] - 1.0 << ", " << fa[2] / f[2] - 1.0);
    for (int i = 0; i < 3; ++i) {
      const double d = std::abs(fr(i) / f[static_cast<std::size_t>(i)] - 1.0);
      WARN("epsilon " << eps << " mode " << i + 1 << ": relative frequency difference " << d);
      CHECK(d <= 3 * eps);  // measured up to 1.17 epsilon
    }
    for (const double w : {0.5 * f[0], 0.5 * (f[0] + f[1]), 0.5 * (f[1] + f[2])}) {
      const Eigen::MatrixXcd Gc = response(c.ss, 2 * kPi * w), Gr = response(r.ss, 2 * kPi * w);
      // Position outputs from every input; velocity and acceleration from the tip force (the
      // base positions' rates are the dropped terms).
      double worst = 0.0;
      for (int oi = 0; oi < 5; ++oi)
        for (int j = 0; j < 3; ++j) {
          if (oi >= 3 && j > 0) continue;
          const double ref = std::abs(Gr(oi, j));
          if (ref == 0.0) continue;
          worst = std::max(worst, std::abs(Gc(oi, j) - Gr(oi, j)) / ref);
        }
      WARN("epsilon " << eps << ", " << w << " Hz: largest relative difference " << worst);
      CHECK(worst <= 30 * eps);  // measured up to 10.8 epsilon
    }
  }
}

TEST_CASE(
    "lumped-mass cantilever: damping on the massless directions is reported, a massless "
    "mechanism is refused",
    "[model][massless]") {
  Options damped = opts(Coordinates::kNodal);
  damped.bending_damping = 0.5;
  const Built b = build(cantilever(5, damped), {"force:y.5"}, {"pos:y.5"});
  CHECK(b.c.massless_count == 5);
  CHECK(b.c.damping_coupling > 0.01);  // measured 0.075
  // Damped, stable: every pole in the left half plane.
  CHECK(Eigen::EigenSolver<Eigen::MatrixXd>(b.ss.A, false).eigenvalues().real().maxCoeff() < 0.0);

  // The tip hinge (e3 of the last beam released) leaves phi.5 without mass and stiffness.
  Options hinge = opts(Coordinates::kNodal);
  hinge.tip_release = "released";
  CHECK_THROWS_AS(build(cantilever(5, hinge), {"force:y.5"}, {"pos:y.5"}),
                  flexloop::common::InputError);
  CHECK_THROWS_WITH(build(cantilever(5, hinge), {"force:y.5"}, {"pos:y.5"}),
                    Catch::Contains("massless mechanism") && Catch::Contains("phi.5"));
}

TEST_CASE("lumped-mass cantilever: the model file in tests/model/models", "[model][massless]") {
  // tests/model/models/lumped_cantilever.toml: the deformations model, n = 10 (the file the
  // README's flexloop linearise line uses).
  const auto m = model::load_model("tests/model/models/lumped_cantilever.toml");
  const auto lin = model::linearise(m);
  lti::Condensation c;
  const auto ss = lti::build_state_space(m, lin, {"force:y.10"}, {"pos:y.10"}, &c);
  CHECK(c.massless_count == 10);
  const std::vector<double> f = frequencies_hz(ss.A);
  REQUIRE(f.size() == 10);
  for (int i = 0; i < 3; ++i) {
    const double err =
        (f[static_cast<std::size_t>(i)] - euler_bernoulli_hz(i)) / euler_bernoulli_hz(i);
    CHECK(err < 0.0);
    CHECK(-err < kBound[1][i]);
  }
  CHECK(dc_gain(ss)(0, 0) == Approx(std::pow(kL, 3) / (3 * kE * kI)).epsilon(1e-9));
}
