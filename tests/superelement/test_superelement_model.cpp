// SPDX-License-Identifier: BSD-3-Clause
// [[superelement]] in a model file (issue 58): the reduced body joins the model's coordinates,
// and the linearised model has the frequencies of independent references: the analytic ones of
// a fixed-free spring-mass chain, w_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N + 1))), and those of
// the full sparse pencil with a truss's stiffness added (the Lanczos of craig_bampton.hpp, no
// reduction).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/superelement/craig_bampton.hpp"
#include "plant/superelement/sparse_text.hpp"
#include "tests/superelement/chain_files.hpp"

using namespace flexloop;
using namespace flexloop::plant;

namespace {

// The chain's files in a fresh folder of the test's.
std::filesystem::path chain_body(const std::string& name, int n, double k, double m) {
  const auto dir = test::temp_dir("model_" + name);
  test::write_chain(dir, n, k, m);
  test::write_chain_maps(dir, n);
  return dir;
}

std::string chain_superelement(int tip, double cut_off_hz) {
  return "[[superelement]]\nid = \"chain\"\nformat = \"matrix_market\"\nstiffness = \"K.mtx\"\n"
         "mass = \"M.mtx\"\ndofs = \"dofs.csv\"\nnodes = \"nodes.csv\"\nmodes_up_to_hz = " +
         std::to_string(cut_off_hz) + "\ninterface = { tip = " + std::to_string(tip) + " }\n";
}

model::Model model_in(const std::filesystem::path& dir, const std::string& text) {
  std::ofstream(dir / "model.toml") << text;
  return model::load_model((dir / "model.toml").string());
}

// The linearised model's natural frequencies (Hz, ascending): every coordinate is dynamic here.
Eigen::VectorXd model_hz(const model::Model& m) {
  const model::Linearisation L = model::linearise(m);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(L.K, L.M);
  return ges.eigenvalues().cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
}

}  // namespace

TEST_CASE(
    "superelement model: a chain alone (no nodes, no coordinates table) has the chain's "
    "frequencies",
    "[superelement]") {
  const int n = 300;
  const double k = 1e9, mass = 0.5;
  const auto dir = chain_body("alone", n, k, mass);
  const model::Model m =
      model_in(dir, "[model]\nname = \"chain\"\n" + chain_superelement(n, 2000.0));
  // The tip's x is dynamic; its y and z, which the FE tool does not carry, are fixed; then the
  // kept modes.
  REQUIRE(m.superelements.size() == 1);
  const auto& body = m.superelements[0];
  REQUIRE(body.mode_count() > 20);
  CHECK(body.fixed_interface_hz.maxCoeff() <= 2000.0);
  REQUIRE(m.nd() == 1 + body.mode_count());
  CHECK(m.generalised[0] == "x.tip");
  CHECK(m.generalised[1] == "eta1.chain");
  CHECK(m.coordinate_roles[m.coordinate_index("y.tip")] == model::CoordinateRole::kFixed);
  CHECK(m.x_reference(m.coordinate_index("x.tip")) == Approx(0.01 * n));
  // Every mode is the reduction's own (the model adds nothing to a body alone), to rounding...
  const Eigen::VectorXd f = model_hz(m);
  const plant::superelement::CraigBampton cb = plant::superelement::craig_bampton(
      plant::superelement::read_matrix_market((dir / "K.mtx").string()),
      plant::superelement::read_matrix_market((dir / "M.mtx").string()), {n - 1}, 2000.0);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reduced(cb.K, cb.M);
  REQUIRE(reduced.eigenvalues().size() == f.size());
  for (Eigen::Index j = 0; j < f.size(); ++j)
    CHECK(f(j) == Approx(std::sqrt(reduced.eigenvalues()(j)) / numeric::kTwoPi).epsilon(1e-9));
  // ... and below f_cut / 20 the chain's, from above (Rayleigh-Ritz), to 2e-6; higher up the
  // truncation shows (measured: 1.2e-5 at f_cut / 11, 2e-4 at f_cut / 3.6).
  for (int j = 1; test::chain_hz(n, k, mass, j) < 100.0; ++j) {
    INFO("mode " << j);
    const double exact = test::chain_hz(n, k, mass, j);
    CHECK(f(j - 1) >= exact * (1 - 1e-12));
    CHECK(f(j - 1) <= exact * (1 + 2e-6));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "superelement model: a truss to the ground on its interface node gives the full pencil's "
    "frequencies, and the residual's derivative is the linearised stiffness",
    "[superelement]") {
  const int n = 250;
  const double k = 1e9, mass = 0.5, ks = 4e8;
  const auto dir = chain_body("truss", n, k, mass);
  const model::Model m = model_in(
      dir, "[model]\nname = \"chain on a spring\"\n" + chain_superelement(n, 3000.0) +
               "[[node]]\nid = \"g\"\nposition = [" + std::to_string(0.01 * n + 0.2) +
               ", 0, 0]\n[[element]]\nid = \"s\"\ntype = \"truss\"\nnodes = [\"tip\", \"g\"]\n"
               "stiffness = " +
               std::to_string(ks) + "\n[coordinates]\nfixed_nodes = [\"g\"]\n");
  plant::superelement::SparseMatrix K =
      plant::superelement::read_matrix_market((dir / "K.mtx").string());
  K.coeffRef(n - 1, n - 1) += ks;
  const plant::superelement::SparseMatrix M =
      plant::superelement::read_matrix_market((dir / "M.mtx").string());
  const Eigen::VectorXd full = plant::superelement::sparse_natural_frequencies_hz(K, M, 1000.0, n);
  const Eigen::VectorXd f = model_hz(m);
  REQUIRE(full.size() >= 6);
  for (Eigen::Index j = 0; j < 6; ++j) {
    INFO("mode " << j + 1);
    CHECK(f(j) == Approx(full(j)).epsilon(1e-5));
  }
  // K = dR/dq by central differences of the nonlinear residual about the reference.
  const model::Linearisation L = model::linearise(m);
  const Eigen::VectorXd q0 = model::reference_generalised(m), zero = Eigen::VectorXd::Zero(m.nq());
  CHECK(model::equations_of_motion_residual(m, q0, zero, zero).norm() <= 1e-6 * ks);
  for (int c = 0; c < std::min(m.nq(), 4); ++c) {
    const double h = 1e-7;
    Eigen::VectorXd qp = q0, qm = q0;
    qp(c) += h;
    qm(c) -= h;
    const Eigen::VectorXd dR = (model::equations_of_motion_residual(m, qp, zero, zero) -
                                model::equations_of_motion_residual(m, qm, zero, zero)) /
                               (2 * h);
    INFO("column " << c);
    CHECK((dR - (L.K + L.G).col(c)).norm() <= 1e-5 * L.K.cwiseAbs().maxCoeff());
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("superelement model: bad superelement entries are refused naming the file and entry",
          "[superelement]") {
  const auto dir = chain_body("bad", 30, 1e9, 0.5);
  const auto refused = [&](const std::string& text, const std::string& where,
                           const std::string& what) {
    try {
      model_in(dir, text);
      FAIL("not refused: " << what);
    } catch (const common::InputError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(where) != std::string::npos);
      CHECK(std::string(e.what()).find(what) != std::string::npos);
    }
  };
  const std::string head = "[model]\nname = \"x\"\n";
  refused(head + chain_superelement(31, 2000.0), "nodes.csv", "has no node 31");
  std::ofstream(dir / "nodes.csv", std::ios::app) << "99,1,0,0\n";
  refused(head + chain_superelement(99, 2000.0), "dofs.csv", "no translation of interface node 99");
  refused(head + chain_superelement(30, 1.0), "model.toml:10",
          "modes_up_to_hz = 1 keeps no fixed-interface mode");
  refused("[model]\ndimension = 2\n" + chain_superelement(30, 2000.0), "model.toml:3", "3-D body");
  refused(head + chain_superelement(30, 2000.0) + "[[node]]\nid = \"tip\"\nposition = [0,0,0]\n",
          "model.toml", "interface node id 'tip' is already a node");
  std::string with_damping = chain_superelement(30, 2000.0);
  with_damping.insert(with_damping.find("interface"), "damping = \"C.mtx\"\n");
  refused(head + with_damping, "model.toml:", "damping_ratio");
  std::string bad_format = chain_superelement(30, 2000.0);
  bad_format.replace(bad_format.find("matrix_market"), 13, "nastran");
  refused(head + bad_format, "model.toml:", "'format' must be");
  std::filesystem::remove_all(dir);
}
