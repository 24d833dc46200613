// SPDX-License-Identifier: BSD-3-Clause
// Pads (issue 58): a superelement's interface point spread over a face of mesh nodes, rigid
// (RBE2) or distributing (RBE3), against CalculiX solving the same bar with its own constraints
// (tests/fixtures/make_calculix_pad_bar.py): a steel bar of 24 x 3 x 3 C3D8, 1 m x 0.05 m x
// 0.05 m, clamped at x = 0, its free end face (16 nodes) the pad. Rigid: CalculiX's *RIGID BODY;
// distributing: *EQUATION rows of the equal-weight least-squares rigid fit (written by numpy in
// the fixture). Each with two springs from the pad's reference point to held points (along x
// and z: frequencies), and without them under a moment about y (statics: the pad node's
// rotation, read from its Euler parameters); and a rigid beam from the rigid pad to a point mass.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "tests/superelement/calculix_run.hpp"

using namespace flexloop;

namespace {

constexpr long kReference = 9001, kRotation = 9002;  // the fixture's REF NODE and ROT NODE
constexpr double kMoment = 1.0e3;                    // N m about y, as the fixture applies it

struct PadBar {
  std::filesystem::path dir;
  std::vector<long> face;  // the end face's 16 mesh nodes
};

// The decks written and every CalculiX job run, once per process.
const PadBar& pad_bar() {
  static const PadBar bar = [] {
    test::require_calculix();
    static const test::RemovedAtExit cleanup{
        std::filesystem::temp_directory_path() /
        ("flexloop_test_superelement_pads_" + std::to_string(::getpid()))};
    PadBar b{cleanup.dir, {}};
    std::filesystem::create_directories(b.dir);
    const std::string d = b.dir.string();
    test::run("/usr/bin/python3 tests/fixtures/make_calculix_pad_bar.py --hex 24 3 3 -o " + d);
    for (const char* job :
         {"bar_k", "bar_f", "rigid_f", "rigid_s", "dist_f", "dist_s", "rigid_mass_f"})
      test::run("cd " + d + " && OMP_NUM_THREADS=1 ccx -i " + job + " > " + job + ".log 2>&1");
    std::ifstream face(b.dir / "pad_nodes.txt");
    for (long node = 0; face >> node;) b.face.push_back(node);
    return b;
  }();
  return bar;
}

// A model of the bar with one pad "tip" (`pad`: its keys after id), and when `springs` two
// trusses of 10^6 N/m from the pad node to held nodes 0.5 m away along x and along z.
std::string pad_model(const std::string& pad, bool springs) {
  std::ostringstream m;
  m << "[model]\nname = \"pad bar\"\n[[superelement]]\nid = \"bar\"\nformat = \"calculix\"\n"
    << "stiffness = \"bar_k.sti\"\nmass = \"bar_k.mas\"\ndofs = \"bar_k.dof\"\n"
    << "nodes = \"bar_k.inp\"\nmodes_up_to_hz = 20000\n[[superelement.pad]]\nid = \"tip\"\n"
    << pad << "\n";
  if (springs)
    m << "[[node]]\nid = \"gx\"\nposition = [1.5, 0.025, 0.025]\n"
      << "[[node]]\nid = \"gz\"\nposition = [1.0, 0.025, 0.525]\n"
      << "[[element]]\nid = \"sx\"\ntype = \"truss\"\nnodes = [\"gx\", \"tip\"]\n"
      << "stiffness = 1.0e6\n"
      << "[[element]]\nid = \"sz\"\ntype = \"truss\"\nnodes = [\"gz\", \"tip\"]\n"
      << "stiffness = 1.0e6\n[coordinates]\nfixed_nodes = [\"gx\", \"gz\"]\n";
  return m.str();
}

std::string face_list(const PadBar& bar) {
  std::string s = "nodes = [";
  for (std::size_t i = 0; i < bar.face.size(); ++i)
    s += (i ? ", " : "") + std::to_string(bar.face[i]);
  return s + "]";
}

// The end face by a ball: its corners lie 0.035 m from the centroid, the next layer 0.042 m.
const char* const kFaceBall = "within = { center = [1.0, 0.025, 0.025], radius = 0.04 }";

plant::model::Model load_pad_model(const PadBar& bar, const std::string& name,
                                   const std::string& text) {
  std::ofstream(bar.dir / name) << text;
  return plant::model::load_model((bar.dir / name).string());
}

Eigen::VectorXd pad_model_hz(const plant::model::Model& m) {
  const plant::model::Linearisation L = plant::model::linearise(m);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(
      L.K.topLeftCorner(m.nd(), m.nd()), L.M.topLeftCorner(m.nd(), m.nd()));
  return ges.eigenvalues().cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
}

// The model's frequencies below f_cut / 10 against a CalculiX job's, each within `tolerance`,
// from above (Craig-Bampton is a Rayleigh-Ritz reduction).
void compare_below_tenth_of_cut(const Eigen::VectorXd& ours, const std::filesystem::path& dat,
                                double tolerance) {
  const std::vector<double> theirs = test::calculix_eigenvalues(dat);
  REQUIRE(theirs.size() == 10);
  int compared = 0;
  for (std::size_t j = 0; j < theirs.size(); ++j) {
    const double ccx = std::sqrt(theirs[j]) / numeric::kTwoPi;
    if (ccx > 2000.0) break;
    const double rel = ours(static_cast<Eigen::Index>(j)) / ccx - 1;
    INFO("mode " << j + 1 << ": flexloop " << ours(static_cast<Eigen::Index>(j)) << " Hz, CalculiX "
                 << ccx << " Hz, relative " << rel);
    CHECK(rel >= -2e-7);  // CalculiX's printed eigenvalue: 7 digits
    CHECK(rel <= tolerance);
    ++compared;
  }
  CHECK(compared >= 8);
}

// The pad node's static motion under a moment about y: K q = f with f on l2.tip = 2 M (virtual
// work M d(theta_y), theta = 2 (l1, l2, l3) at the reference orientation); theta_y = 2 q(l2).
std::pair<double, double> tip_under_moment(const plant::model::Model& m) {
  const plant::model::Linearisation L = plant::model::linearise(m);
  const int nd = m.nd();
  const auto index = [&](const std::string& label) {
    const auto it = std::find(m.generalised.begin(), m.generalised.end(), label);
    REQUIRE(it != m.generalised.end());
    return static_cast<Eigen::Index>(it - m.generalised.begin());
  };
  Eigen::VectorXd f = Eigen::VectorXd::Zero(nd);
  f(index("l2.tip")) = 2 * kMoment;
  const Eigen::VectorXd q = L.K.topLeftCorner(nd, nd).ldlt().solve(f);
  return {2 * q(index("l2.tip")), q(index("z.tip"))};
}

}  // namespace

TEST_CASE(
    "superelement pads: a rigid pad on the bar's end face has CalculiX's *RIGID BODY "
    "frequencies below f_cut / 10, its rotation CalculiX's under a moment",
    "[superelement]") {
  const PadBar& bar = pad_bar();
  const plant::model::Model m = load_pad_model(
      bar, "rigid_f.toml", pad_model(std::string(kFaceBall) + "\nkind = \"rigid\"", true));
  const auto tip_at = std::find_if(m.nodes.begin(), m.nodes.end(),
                                   [](const plant::model::Node& n) { return n.id == "tip"; });
  REQUIRE(tip_at != m.nodes.end());
  const plant::model::Node& tip = *tip_at;
  CHECK(tip.rotational);
  CHECK((tip.position - Eigen::Vector3d(1.0, 0.025, 0.025)).norm() <= 1e-12);
  // The pad node's x, y, z and l1..l3, then the modes; l0 dependent (euler.tip).
  for (const char* c : {"x.tip", "y.tip", "z.tip", "l1.tip", "l2.tip", "l3.tip"})
    CHECK(std::find(m.generalised.begin(), m.generalised.end(), c) != m.generalised.end());
  CHECK(m.coordinate_roles[static_cast<std::size_t>(m.coordinate_index("l0.tip"))] ==
        plant::model::CoordinateRole::kDependent);
  // Measured: 1.8e-8 (mode 1) ... 3.9e-5 (mode 10, 1577 Hz), the reduction's truncation.
  compare_below_tenth_of_cut(pad_model_hz(m), bar.dir / "rigid_f.dat", 1e-4);

  const auto [theta_y, tip_z] = tip_under_moment(load_pad_model(
      bar, "rigid_s.toml", pad_model(std::string(kFaceBall) + "\nkind = \"rigid\"", false)));
  const auto rotation = test::calculix_displacement(bar.dir / "rigid_s.dat", kRotation);
  const auto reference = test::calculix_displacement(bar.dir / "rigid_s.dat", kReference);
  // CalculiX's ROT NODE carries the rotation as its displacement; 7 printed digits.
  CHECK(theta_y == Approx(rotation[1]).epsilon(1e-6));
  CHECK(tip_z == Approx(reference[2]).epsilon(1e-6));
  // Beam theory, free of the mesh's stiffness: a pure moment bends the bar to a circular arc,
  // tip deflection -theta L / 2 (L = 1 m); theta_y > 0 for a moment about +y.
  CHECK(theta_y > 0);
  CHECK(tip_z == Approx(-theta_y / 2).epsilon(1e-4));
}

TEST_CASE(
    "superelement pads: a distributing pad does not stiffen the bar, and has CalculiX's "
    "frequencies and rotation with the same *EQUATION constraint",
    "[superelement]") {
  const PadBar& bar = pad_bar();
  const std::string pad = face_list(bar) + "\nkind = \"distributing\"";
  // Alone, the pad adds six coordinates and no stiffness: the bare bar's frequencies. Measured
  // up to 4.4e-5 (mode 10) bare and on springs, the reduction's truncation.
  compare_below_tenth_of_cut(
      pad_model_hz(load_pad_model(bar, "dist_bare.toml", pad_model(pad, false))),
      bar.dir / "bar_f.dat", 1e-4);
  compare_below_tenth_of_cut(pad_model_hz(load_pad_model(bar, "dist_f.toml", pad_model(pad, true))),
                             bar.dir / "dist_f.dat", 1e-4);
  const auto [theta_y, tip_z] =
      tip_under_moment(load_pad_model(bar, "dist_s.toml", pad_model(pad, false)));
  const auto rotation = test::calculix_displacement(bar.dir / "dist_s.dat", kRotation);
  const auto reference = test::calculix_displacement(bar.dir / "dist_s.dat", kReference);
  CHECK(theta_y == Approx(rotation[1]).epsilon(1e-6));
  CHECK(tip_z == Approx(reference[2]).epsilon(1e-6));
  // The face is free to warp under the pad: the mean rotation exceeds the rigid face's.
  const auto rigid = test::calculix_displacement(bar.dir / "rigid_s.dat", kRotation);
  CHECK(theta_y > rigid[1] * (1 + 1e-3));
}

TEST_CASE(
    "superelement pads: a rigid beam from a rigid pad's node carries a point mass off the bar's "
    "axis, as CalculiX's rigid body with the mass in it",
    "[superelement]") {
  // The pad node's rotations drive the beam: the 2 kg mass 0.1 m beyond the face and off the
  // axis (fixture: ARM) couples the pad's translations, rotations and the bar's torsion.
  const PadBar& bar = pad_bar();
  const std::string arm =
      "[[node]]\nid = \"p\"\nposition = [1.1, 0.05, 0.0]\nmass = 2.0\nrotational = true\n"
      "[[element]]\nid = \"arm\"\ntype = \"beam\"\nnodes = [\"tip\", \"p\"]\n"
      "modes = [\"rigid\", \"rigid\", \"rigid\", \"rigid\", \"rigid\", \"rigid\"]\n";
  const plant::model::Model m =
      load_pad_model(bar, "rigid_mass.toml",
                     pad_model(std::string(kFaceBall) + "\nkind = \"rigid\"", false) + arm);
  CHECK(m.coordinate_roles[static_cast<std::size_t>(m.coordinate_index("x.p"))] ==
        plant::model::CoordinateRole::kDependent);
  // Measured 2.4e-9 (mode 1) ... 1.8e-5 (mode 8), the reduction's truncation.
  compare_below_tenth_of_cut(pad_model_hz(m), bar.dir / "rigid_mass_f.dat", 1e-4);
}

namespace {

// The error a model of the bar with these [[superelement.pad]] entries (and `extra` keys in the
// [[superelement]] table) is refused with.
std::string pad_refusal(const std::string& name, const std::string& extra,
                        const std::vector<std::string>& pads) {
  const PadBar& bar = pad_bar();
  std::ostringstream m;
  m << "[model]\nname = \"bad pads\"\n[[superelement]]\nid = \"bar\"\nformat = \"calculix\"\n"
    << "stiffness = \"bar_k.sti\"\nmass = \"bar_k.mas\"\ndofs = \"bar_k.dof\"\n"
    << "nodes = \"bar_k.inp\"\nmodes_up_to_hz = 20000\n"
    << extra << "\n";
  for (const std::string& pad : pads) m << "[[superelement.pad]]\n" << pad << "\n";
  try {
    load_pad_model(bar, name, m.str());
  } catch (const common::InputError& e) {
    return e.what();
  }
  FAIL("the model " << name << " was accepted");
  return {};
}

}  // namespace

TEST_CASE("superelement pads: bad pads are refused at their entry", "[superelement]") {
  using Catch::Matchers::Contains;
  // The end face is nodes 385..400 (i = 24: 385 + 4 j + k); 385..388 lie on one line.
  CHECK_THAT(pad_refusal("few.toml", "", {"id = \"p\"\nnodes = [385, 386]\nkind = \"rigid\""}),
             Contains("few.toml:12: superelement.pad: has 2 mesh node(s): a pad needs 3"));
  CHECK_THAT(pad_refusal("line.toml", "",
                         {"id = \"p\"\nnodes = [385, 386, 387, 388]\nkind = \"distributing\""}),
             Contains("line.toml:12") && Contains("nodes on one line"));
  CHECK_THAT(pad_refusal("none.toml", "",
                         {"id = \"p\"\nwithin = { center = [3.0, 0, 0], radius = 0.1 }\n"
                          "kind = \"rigid\""}),
             Contains("none.toml:12") && Contains("'within' catches no node of"));
  CHECK_THAT(pad_refusal("pin.toml", "interface = { c = 385 }",
                         {"id = \"p\"\nnodes = [385, 390, 395]\nkind = \"rigid\""}),
             Contains("pin.toml:12") && Contains("mesh node 385 is also an 'interface' node"));
  CHECK_THAT(pad_refusal("twice.toml", "",
                         {"id = \"p\"\nnodes = [385, 390, 395]\nkind = \"rigid\"",
                          "id = \"q\"\nnodes = [390, 391, 400]\nkind = \"rigid\""}),
             Contains("twice.toml:16") && Contains("mesh node 390 is also in pad 1"));
  CHECK_THAT(pad_refusal("same_id.toml", "interface = { p = 385 }",
                         {"id = \"p\"\nnodes = [390, 391, 400]\nkind = \"rigid\""}),
             Contains("same_id.toml:13") && Contains("pad id 'p' is also an 'interface' node id"));
  CHECK_THAT(
      pad_refusal("kind.toml", "", {"id = \"p\"\nnodes = [390, 391, 400]\nkind = \"welded\""}),
      Contains("kind.toml:15") && Contains("unknown kind 'welded'"));
  CHECK_THAT(pad_refusal("both.toml", "",
                         {"id = \"p\"\nnodes = [390, 391, 400]\nkind = \"rigid\"\n"
                          "within = { center = [1.0, 0.025, 0.025], radius = 0.04 }"}),
             Contains("both.toml:12") && Contains("give either 'nodes'"));
  CHECK_THAT(
      pad_refusal("absent.toml", "", {"id = \"p\"\nnodes = [390, 391, 99999]\nkind = \"rigid\""}),
      Contains("absent.toml:12") && Contains("mesh node 99999 is not in"));
  CHECK_THAT(pad_refusal("held.toml", "", {"id = \"p\"\nnodes = [1, 2, 5]\nkind = \"rigid\""}),
             Contains("held.toml:12") && Contains("mesh node 1 lacks a translation"));
}
