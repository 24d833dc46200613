// SPDX-License-Identifier: BSD-3-Clause
// Superelements (issue 58) against an outside solver: a steel bar of C3D8 elements, 1 m x 0.05 m
// x 0.05 m, clamped at x = 0 (tests/fixtures/make_calculix_bar.py), given to CalculiX twice:
// *FREQUENCY,SOLVER=MATRIXSTORAGE for K, M and the row map, read by flexloop's readers, and a
// plain *FREQUENCY whose eigenvalue table (jobname.dat) is the reference. ccx is a project
// dependency (tools/lib/common.sh installs calculix-ccx): the test fails without it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include "numeric/constants.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "plant/superelement/craig_bampton.hpp"
#include "plant/superelement/sparse_text.hpp"
#include "tests/superelement/calculix_run.hpp"

using namespace flexloop;
using namespace flexloop::plant::superelement;
using flexloop::test::calculix_eigenvalues;
using flexloop::test::run;

namespace {

struct CalculixBar {
  std::filesystem::path dir;
  std::vector<double> reference_hz;  ///< CalculiX's own, from its eigenvalue table
  SparseMatrix K, M;
  std::vector<DofLabel> dofs;
  std::vector<long> interface_nodes;  ///< the free end's four corners
};

// Made once per process: the decks, both ccx runs, the matrices read.
const CalculixBar& calculix_bar() {
  static const CalculixBar bar = [] {
    test::require_calculix();
    CalculixBar b;
    // Removed at exit even when a step below fails.
    static const test::RemovedAtExit cleanup{
        std::filesystem::temp_directory_path() /
        ("flexloop_test_superelement_calculix_" + std::to_string(::getpid()))};
    b.dir = cleanup.dir;
    std::filesystem::create_directories(b.dir);
    const std::string d = b.dir.string();
    run("/usr/bin/python3 tests/fixtures/make_calculix_bar.py --hex 24 3 3 --length 1 --width "
        "0.05 --height 0.05 --modes 10 -o " +
        d + " > /dev/null");
    run("cd " + d + " && OMP_NUM_THREADS=1 ccx -i bar_k > bar_k.log 2>&1");
    run("cd " + d + " && OMP_NUM_THREADS=1 ccx -i bar_f > bar_f.log 2>&1");
    for (const double lambda : calculix_eigenvalues(b.dir / "bar_f.dat"))
      b.reference_hz.push_back(std::sqrt(lambda) / numeric::kTwoPi);
    b.dofs = read_calculix_dofs(d + "/bar_k.dof");
    const auto n = static_cast<Eigen::Index>(b.dofs.size());
    b.K = read_calculix_matrix(d + "/bar_k.sti", n);
    b.M = read_calculix_matrix(d + "/bar_k.mas", n);
    std::ifstream corners(b.dir / "interface_nodes.txt");
    for (long node = 0; corners >> node;) b.interface_nodes.push_back(node);
    return b;
  }();
  return bar;
}

// The rows of `nodes`' DOFs, in the order of the row map.
std::vector<Eigen::Index> rows_of(const std::vector<DofLabel>& dofs,
                                  const std::vector<long>& nodes) {
  std::vector<Eigen::Index> rows;
  for (std::size_t r = 0; r < dofs.size(); ++r)
    if (std::find(nodes.begin(), nodes.end(), dofs[r].node) != nodes.end())
      rows.push_back(static_cast<Eigen::Index>(r));
  return rows;
}

// The time since `start` (s) and the process's peak resident set so far (MiB).
struct Lap {
  double seconds = 0, peak_mib = 0;
};
Lap lap(std::chrono::steady_clock::time_point start) {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          static_cast<double>(usage.ru_maxrss) / 1024.0};
}

Eigen::VectorXd reduced_model_hz(const CraigBampton& cb) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(cb.K, cb.M);  // dense: small
  return ges.eigenvalues().cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
}

}  // namespace

TEST_CASE(
    "superelement: a CalculiX bar's matrices (.sti, .mas, .dof) give CalculiX's own ten lowest "
    "frequencies",
    "[superelement]") {
  const CalculixBar& bar = calculix_bar();
  // 24 x 3 x 3 C3D8: 25 x 16 nodes, the 16 at x = 0 held, 3 DOFs each.
  REQUIRE(bar.dofs.size() == 3 * (400 - 16));
  REQUIRE(bar.reference_hz.size() == 10);
  const Eigen::VectorXd full =
      sparse_natural_frequencies_hz(bar.K, bar.M, 1.1 * bar.reference_hz.back(), 10);
  REQUIRE(full.size() == 10);
  // Measured: 6.9e-8 at most (mode 3), the rounding of CalculiX's printed eigenvalue (7
  // significant digits: up to 1.5e-7 of it, half that in the frequency).
  for (Eigen::Index j = 0; j < 10; ++j) {
    INFO("mode " << j + 1 << ": " << full(j) << " Hz, CalculiX " << bar.reference_hz[j] << " Hz");
    CHECK(std::abs(full(j) - bar.reference_hz[static_cast<std::size_t>(j)]) <=
          1e-6 * bar.reference_hz[static_cast<std::size_t>(j)]);
  }
}

TEST_CASE(
    "superelement: the CalculiX bar reduced by Craig-Bampton to its free end's four corners has "
    "the full model's frequencies below f_cut / 10, from above",
    "[superelement]") {
  const CalculixBar& bar = calculix_bar();
  const std::vector<Eigen::Index> interface = rows_of(bar.dofs, bar.interface_nodes);
  REQUIRE(interface.size() == 12);
  // f_cut = 10 kHz: 28 fixed-interface modes; below 1 kHz (seven modes) the reduced model's
  // frequencies exceed the full one's by 3.3e-7 (first) to 9.4e-5 (sixth, seventh), measured.
  const double f_cut = 10000.0;
  const CraigBampton cb = craig_bampton(bar.K, bar.M, interface, f_cut);
  CHECK(cb.interface_dofs == 12);
  CHECK(cb.fixed_interface_hz.maxCoeff() <= f_cut);
  const Eigen::VectorXd reduced = reduced_model_hz(cb);
  const Eigen::VectorXd full = sparse_natural_frequencies_hz(bar.K, bar.M, f_cut / 10, 100);
  REQUIRE(full.size() == 7);
  for (Eigen::Index j = 0; j < full.size(); ++j) {
    INFO("mode " << j + 1 << ": reduced " << reduced(j) << " Hz, full " << full(j) << " Hz");
    CHECK(reduced(j) >= full(j) * (1 - 1e-9));
    CHECK(reduced(j) - full(j) <= 2e-4 * full(j));
  }
}

namespace {

// tests/bench/superelement_vs_calculix.sh: the import, the reduction and the reduced model's
// eigenvalues, each phase timed, for a bar that script gave CalculiX.
struct BenchResult {
  Eigen::Index dofs = 0, modes = 0;
  Lap dof_map, stiffness, mass, reduction, eigenvalues;
  Eigen::VectorXd reduced_hz;
};

BenchResult bench_reduction(const std::filesystem::path& dir, double f_cut) {
  BenchResult r;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<DofLabel> dofs = read_calculix_dofs((dir / "bar_k.dof").string());
  r.dofs = static_cast<Eigen::Index>(dofs.size());
  r.dof_map = lap(start);
  const SparseMatrix K = read_calculix_matrix((dir / "bar_k.sti").string(), r.dofs);
  r.stiffness = lap(start);
  const SparseMatrix M = read_calculix_matrix((dir / "bar_k.mas").string(), r.dofs);
  r.mass = lap(start);
  std::vector<long> corners;
  std::ifstream in(dir / "interface_nodes.txt");
  for (long node = 0; in >> node;) corners.push_back(node);
  const CraigBampton cb = craig_bampton(K, M, rows_of(dofs, corners), f_cut);
  r.modes = cb.fixed_interface_hz.size();
  r.reduction = lap(start);
  r.reduced_hz = reduced_model_hz(cb);
  r.eigenvalues = lap(start);
  return r;
}

}  // namespace

TEST_CASE("superelement: bench, a CalculiX bar's import and reduction (FLEXLOOP_BENCH_DIR)",
          "[.bench]") {
  const char* dir = std::getenv("FLEXLOOP_BENCH_DIR");
  if (!dir) FAIL("FLEXLOOP_BENCH_DIR: the folder of bar_k.{sti,mas,dof} and bar_f.dat");
  const char* cut = std::getenv("FLEXLOOP_BENCH_CUT_HZ");
  const double f_cut = cut ? std::atof(cut) : 4000.0;
  const BenchResult r = bench_reduction(dir, f_cut);
  const std::vector<double> reference =
      calculix_eigenvalues(std::filesystem::path(dir) / "bar_f.dat");
  std::printf("dofs %ld, interface 12, fixed-interface modes below %g Hz: %ld\n",
              static_cast<long>(r.dofs), f_cut, static_cast<long>(r.modes));
  for (const auto& [name, l] : {std::pair{"dof map", r.dof_map},
                                {"+ K", r.stiffness},
                                {"+ M", r.mass},
                                {"+ reduction", r.reduction},
                                {"+ eigenvalues", r.eigenvalues}})
    std::printf("%-15s %8.2f s  peak RSS %7.0f MiB\n", name, l.seconds, l.peak_mib);
  double worst = 0;
  for (std::size_t j = 0; j < reference.size(); ++j) {
    const double ccx = std::sqrt(reference[j]) / numeric::kTwoPi;
    const double ours = r.reduced_hz(static_cast<Eigen::Index>(j));
    worst = std::max(worst, std::abs(ours - ccx) / ccx);
    std::printf("mode %zu  reduced %.7g Hz  CalculiX %.7g Hz  relative %+.2e\n", j + 1, ours, ccx,
                (ours - ccx) / ccx);
  }
  std::printf("worst relative difference %.2e\n", worst);
  CHECK(worst <= 1e-3);
}

TEST_CASE(
    "superelement: the CalculiX bar as a [[superelement]] of a model file (its deck's *NODE for "
    "the interface) linearises to CalculiX's own frequencies below f_cut / 10",
    "[superelement]") {
  const CalculixBar& bar = calculix_bar();
  std::ostringstream model;
  model << "[model]\nname = \"CalculiX bar\"\n[[superelement]]\nid = \"bar\"\n"
        << "format = \"calculix\"\nstiffness = \"bar_k.sti\"\nmass = \"bar_k.mas\"\n"
        << "dofs = \"bar_k.dof\"\nnodes = \"bar_k.inp\"\nmodes_up_to_hz = 10000\n"
        << "damping_ratio = 0.01\ninterface = { ";
  for (std::size_t c = 0; c < bar.interface_nodes.size(); ++c)
    model << (c ? ", " : "") << "c" << c + 1 << " = " << bar.interface_nodes[c];
  model << " }\n";
  std::ofstream(bar.dir / "bar.toml") << model.str();
  const plant::model::Model m = plant::model::load_model((bar.dir / "bar.toml").string());
  REQUIRE(m.nodes.size() == 4);
  CHECK(m.nodes[0].position(0) == Approx(1.0));  // the free end, from the deck's *NODE
  const plant::model::Linearisation L = plant::model::linearise(m);
  REQUIRE(m.nd() == m.nq());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(L.K, L.M);
  const Eigen::VectorXd f = ges.eigenvalues().cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
  // The same reduction as the case above, now through the model: 3.3e-7 ... 9.4e-5 above the
  // full model's, which is CalculiX's to 7e-8.
  for (std::size_t j = 0; j < 7; ++j) {
    INFO("mode " << j + 1 << ": model " << f(static_cast<Eigen::Index>(j)) << " Hz, CalculiX "
                 << bar.reference_hz[j] << " Hz");
    CHECK(std::abs(f(static_cast<Eigen::Index>(j)) / bar.reference_hz[j] - 1) <= 2e-4);
  }
  // damping_ratio on every mode of the body alone: Phi' D Phi = diag(2 zeta w_j), to rounding.
  const Eigen::MatrixXd& phi = ges.eigenvectors();
  const Eigen::MatrixXd modal = phi.transpose() * L.D * phi;
  const Eigen::VectorXd w = f * numeric::kTwoPi;
  CHECK((modal - Eigen::MatrixXd((2 * 0.01 * w).asDiagonal())).norm() <= 1e-9 * modal.norm());
}
