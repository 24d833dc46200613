// SPDX-License-Identifier: BSD-3-Clause
// Hard case 5 (doc/design.md §9, issue 17): near-buckling preload. The frequencies go to zero
// smoothly as the load factor alpha approaches 1; beyond it the plant is reported statically
// unstable, naming the buckling multiplier, and the loop commands refuse it.
//
// Reference (not produced by the code under test). A pinned-pinned uniform Euler-Bernoulli column
// under an axial compression P: vibration and buckling modes are the same sines, so
//   w_n^2(P) = w_n0^2 (1 - P/P_n),   P_n = n^2 pi^2 EI / L^2,   w_10 = (pi/L)^2 sqrt(EI/(rho A)),
// and the first frequency squared is linear in alpha = P/P_1, through zero at alpha = 1 and
// negative beyond (a divergent mode e^{s t}, s = w_10 sqrt(alpha - 1)).
//
// The discrete column (10 planar beams, rigid axial elongation so that the compressive nodal
// force is carried as a reaction, as in tests/model/test_buckling.cpp; lumped translational mass
// and HRZ rotary inertia on the nodes) obeys this only approximately, and alpha is taken against
// its own first buckling load P_cr = lambda_cr P0 (buckling_multipliers), so that f1 = 0 at
// alpha = 1 exactly. Two departures bound r(alpha) = f1^2 / ((1 - alpha) f1(0)^2):
// - mode mismatch: w1^2(alpha) is concave in alpha (the smallest eigenvalue of a pencil affine in
//   alpha), 0 at alpha = 1, so 1 <= r(alpha) <= r(1) = (phi_b^T K phi_b / phi_b^T M phi_b) / w10^2
//   with phi_b the discrete buckling mode; it is 1 when the discrete vibration and buckling modes
//   coincide. Measured r - 1: 2.7e-8 (0.5), 4.8e-8 (0.9), 5.3e-8 (0.99), 3.5e-8 (0.999), 5.8e-8
//   (0.9995, the largest).
// - rounding: the eigensolver resolves w^2 to about eps w_max^2 absolute, so r carries
//   ~ eps (w_max / w1(0))^2 / (1 - alpha) = 1e-11 / (1 - alpha) here (f_max = 1265 Hz); measured
//   r - 1 = -1.4e-8 at 0.9999, -2.9e-7 at 0.99999. (With 40 beams, w_max^2 is 250 times larger:
//   r - 1 = 2.2e-5 at 0.9999, and from 0.99999 natural_modes reports f1 = 0, the first mode's w^2
//   being then below its rounding threshold 100 n eps w_max^2: zero within rounding.)
// Bound: |r - 1| <= 1e-6 at every alpha tested up to 0.9999 and beyond buckling (measured largest
// 5.8e-8, at 0.9995). The discretisation itself, against the continuous column: P_cr 8.25e-3 above
// Euler's load (bound 1e-2), f1(0) 1.27e-3 below w_10 / 2 pi (bound 2e-3).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop;

namespace {

constexpr int kN = 10;                                                            // beams
constexpr double kL = 2.0, kE = 7.0e10, kA = 3.0e-4, kI = 2.5e-9, kRho = 2700.0;  // SI
using flexloop::numeric::kPi;
constexpr double kBound = 1e-6;  // on |r - 1|, see above

// The column with a compressive force P at node kN. `scene_ready`: node 0's lateral coordinate
// prescribed (the floor) instead of fixed and the first beam's bending e2 actuated, for a scene's
// channels; the dynamic block (and so every mode) is the same.
std::string column(double P, bool scene_ready = false) {
  std::ostringstream os;
  os.precision(17);
  const double l = kL / kN, me = kRho * kA * l;
  os << "[model]\nname = \"column\"\ndimension = 2\n";
  for (int i = 0; i <= kN; ++i) {
    // HRZ rotary inertia, m_e l^2 / 78 per element end, so that every coordinate has mass.
    os << "[[node]]\nid = \"" << i << "\"\nposition = [" << kL * i / kN
       << ", 0.0]\nrotational = true\ninertia = " << (i == 0 || i == kN ? 1 : 2) * me * l * l / 78
       << "\n";
    if (i == kN) os << "force = [" << -P << ", 0.0]\n";
  }
  for (int k = 1; k <= kN; ++k) {
    os << "[[element]]\nid = \"b" << k << "\"\ntype = \"planar_beam\"\nnodes = [\"" << k - 1
       << "\", \"" << k << "\"]\nE = " << kE << "\nA = " << kA << "\nI = " << kI
       << "\nrho = " << kRho << "\nmodes = [\"rigid\", \"flexible\", \"flexible\"]\n";
    if (k == 1 && scene_ready) os << "actuated = [false, true, false]\n";
  }
  os << "[coordinates]\n";
  if (scene_ready)
    os << "fixed = [\"x.0\", \"y." << kN << "\"]\nprescribed = [\"y.0\"]\n";
  else
    os << "fixed = [\"x.0\", \"y.0\", \"y." << kN << "\"]\n";
  os << "dynamic = [";
  for (int k = 1; k <= kN; ++k)
    os << (k > 1 ? ", " : "") << "\"e2.b" << k << "\", \"e3.b" << k << "\"";
  os << "]\n";
  return os.str();
}

struct ColumnModes {
  plant::lti::Modes modes;
  plant::lti::StaticStability statics;
};

// What build_scene_plant does with the column's linearisation (the code under test).
ColumnModes analyse(double P) {
  const auto m = plant::model::parse_model(column(P), "column.toml");
  const auto lin = plant::model::linearise(m);
  const int nd = m.nd();
  ColumnModes c;
  c.modes = plant::lti::natural_modes(lin.M.topLeftCorner(nd, nd),
                                      (lin.K + lin.N + lin.G).topLeftCorner(nd, nd));
  c.statics = plant::lti::static_stability(c.modes, lin.K.topLeftCorner(nd, nd),
                                           lin.G.topLeftCorner(nd, nd));
  return c;
}

// The discrete column's first buckling load [N].
double critical_load() {
  const double p0 = 1000.0;
  const auto s = analyse(p0).statics;
  REQUIRE(s.critical_multiplier > 0);
  return s.critical_multiplier * p0;
}

}  // namespace

TEST_CASE("near buckling: f1^2 falls linearly to zero with the load factor, smoothly",
          "[hard][buckling]") {
  const double pcr = critical_load();
  const double euler = kPi * kPi * kE * kI / (kL * kL);
  const double f_eb = kPi / (2 * kL * kL) * std::sqrt(kE * kI / (kRho * kA));
  const double f0 = analyse(0.0).modes.frequencies_hz(0);
  INFO("P_cr = " << pcr << " N (Euler " << euler << "), f1(0) = " << f0 << " Hz (" << f_eb << ")");
  CHECK(std::abs(pcr / euler - 1) < 1e-2);
  CHECK(std::abs(f0 / f_eb - 1) < 2e-3);

  // r(alpha) = f1^2 / ((1 - alpha) f1(0)^2) at the listed factors, and on a sweep for
  // monotonicity: f1 finite, positive, strictly decreasing; r within the bound (so no jump).
  std::vector<double> alphas;
  for (int k = 0; k < 100; ++k) alphas.push_back(k / 100.0);
  for (double a : {0.995, 0.999, 0.9995, 0.9999}) alphas.push_back(a);
  double previous = HUGE_VAL, worst = 0;
  for (double a : alphas) {
    const ColumnModes c = analyse(a * pcr);
    const double f1 = c.modes.frequencies_hz(0);
    const double r = f1 * f1 / ((1 - a) * f0 * f0);
    INFO("alpha = " << a << ": f1 = " << f1 << " Hz, r - 1 = " << r - 1);
    REQUIRE(std::isfinite(f1));
    CHECK(f1 > 0);
    CHECK(f1 < previous);
    CHECK(std::abs(r - 1) <= kBound);
    CHECK(c.statics.stable());
    previous = f1;
    worst = std::max(worst, std::abs(r - 1));
  }
  WARN("near buckling: largest |f1^2 / ((1 - alpha) f1(0)^2) - 1| up to alpha = 0.9999: "
       << worst << " (bound " << kBound << ")");

  // Beyond buckling the same law, with the sign: w1^2 = (1 - alpha) w1(0)^2 < 0, one divergent
  // mode (the second buckling load is about 4 P_cr) growing at w1(0) sqrt(alpha - 1); the
  // buckling multiplier is 1/alpha.
  for (double a : {1.01, 1.5, 3.0}) {
    const ColumnModes c = analyse(a * pcr);
    const double f1 = c.modes.frequencies_hz(0);
    const double r = -f1 * f1 / ((1 - a) * f0 * f0);
    INFO("alpha = " << a << ": f1 = " << f1 << " Hz, r - 1 = " << r - 1
                    << ", lambda_cr alpha - 1 = " << c.statics.critical_multiplier * a - 1);
    CHECK(f1 < 0);
    CHECK(std::abs(r - 1) <= kBound);
    CHECK_FALSE(c.statics.stable());
    CHECK(c.statics.divergent == 1);
    CHECK(c.statics.flutter == 0);
    CHECK(std::abs(c.statics.growth_rate / (2 * kPi * f0 * std::sqrt(a - 1)) - 1) <= kBound);
    CHECK(std::abs(c.statics.critical_multiplier * a - 1) <= 1e-9);
  }
}

TEST_CASE(
    "beyond buckling the plant is refused by the loop commands, naming the buckling multiplier",
    "[hard][buckling]") {
  const double pcr = critical_load();
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("flexloop_near_buckling_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto write = [](const fs::path& file, const std::string& text) {
    std::ofstream(file) << text;
  };
  const std::string scene_file = (dir / "column.toml").string();
  write(scene_file, R"([scene]
name = "column"
model = "column_model.toml"

[plant]
disturbances = ["acc:y.0"]
actuators = ["stress:e2.b1"]
performance = ["acc:y.5"]
sensors = ["stress:e2.b1"]

[controller]
type = "none"

[discretisation]
method = "zoh"
rate_hz = 1000

[floor]
spectrum = "VC-C"
)");
  struct Case {
    double alpha;
    const char *factor, *multiplier;  // as the message prints them (3 significant digits)
  };
  for (const Case& k :
       {Case{1.01, "1.01", "0.99"}, Case{1.5, "1.5", "0.667"}, Case{3.0, "3", "0.333"}}) {
    write(dir / "column_model.toml", column(k.alpha * pcr, true));
    // The scene's plant is built (analyse reports it from here) ...
    const auto p = scene::build_scene_plant(scene::load_scene(scene_file));
    CHECK_FALSE(p.statics.stable());
    CHECK(std::abs(p.statics.critical_multiplier * k.alpha - 1) <= 1e-9);
    // ... and build, sim, plant, controller and hil (scene::load_loop) refuse it.
    try {
      scene::load_loop(scene_file);
      FAIL("a column at " << k.alpha << " times its buckling load was built");
    } catch (const common::InputError& e) {
      const std::string what = e.what();
      INFO(what);
      CHECK(what.rfind(scene_file + ":3: [scene]: model " + (dir / "column_model.toml").string(),
                       0) == 0);
      CHECK(what.find(std::string("the preload is ") + k.factor +
                      " times the first buckling load (buckling multiplier " + k.multiplier +
                      "): the linearised model is statically unstable, 1 divergent mode") !=
            std::string::npos);
      CHECK(what.find("neither built nor run") != std::string::npos);
    }
  }
  // Below buckling the same scene is built.
  write(dir / "column_model.toml", column(0.5 * pcr, true));
  CHECK_NOTHROW(scene::load_loop(scene_file));
  fs::remove_all(dir);
}

TEST_CASE("static stability without a preload: a negative stiffness is named as such",
          "[hard][buckling]") {
  // Two masses, one on a negative spring (an unlikely mechanism): w^2 = {-4, 9}, no preload.
  const Eigen::Matrix2d M = Eigen::Matrix2d::Identity();
  Eigen::Matrix2d K;
  K << -4, 0, 0, 9;
  const auto s =
      plant::lti::static_stability(plant::lti::natural_modes(M, K), K, Eigen::Matrix2d::Zero());
  CHECK_FALSE(s.stable());
  CHECK_FALSE(s.preloaded);
  CHECK(s.divergent == 1);
  CHECK(s.growth_rate == Approx(2.0).epsilon(1e-12));
  CHECK(plant::lti::to_string(s).rfind(
            "no preload, yet the stiffness is not positive definite: the linearised model is "
            "statically unstable, 1 divergent mode growing as e^(2 t)",
            0) == 0);
}
