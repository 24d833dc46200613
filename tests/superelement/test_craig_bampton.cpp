// SPDX-License-Identifier: BSD-3-Clause
// Superelements (issue 58): the FE tool's matrices read from their text files and reduced by
// Craig-Bampton, against independent references: a fixed-free spring-mass chain's analytic
// frequencies, w_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N + 1))), and (test_calculix.cpp)
// CalculiX's own eigenvalues of the same mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "common/input_error.hpp"
#include "numeric/constants.hpp"
#include "plant/superelement/craig_bampton.hpp"
#include "plant/superelement/sparse_text.hpp"
#include "tests/superelement/chain_files.hpp"

using namespace flexloop;
using namespace flexloop::plant::superelement;
using flexloop::test::chain_hz;
using flexloop::test::temp_dir;
using flexloop::test::write_chain;

namespace {

// The reduced model's natural frequencies (Hz, ascending).
Eigen::VectorXd reduced_hz(const CraigBampton& cb) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(cb.K, cb.M);  // dense: small
  return ges.eigenvalues().cwiseMax(0.0).cwiseSqrt() / numeric::kTwoPi;
}

}  // namespace

TEST_CASE(
    "superelement: a 2000-mass chain from Matrix Market files has the analytic frequencies, by "
    "the sparse Lanczos and by Craig-Bampton to the cut-off",
    "[superelement]") {
  const auto dir = temp_dir("chain");
  const int n = 2000;
  const double k = 1e7, m = 0.5;
  write_chain(dir, n, k, m);
  const SparseMatrix K = read_matrix_market((dir / "K.mtx").string());
  const SparseMatrix M = read_matrix_market((dir / "M.mtx").string(), n);
  REQUIRE(K.nonZeros() == 3 * n - 2);
  // The full model: every mode below 100 Hz.
  const Eigen::VectorXd full = sparse_natural_frequencies_hz(K, M, 100.0, n);
  int below = 0;
  while (chain_hz(n, k, m, below + 1) <= 100.0) ++below;
  REQUIRE(full.size() == below);
  for (int j = 0; j < below; ++j) CHECK(full(j) == Approx(chain_hz(n, k, m, j + 1)).epsilon(1e-9));
  // Held at its free end (the interface), reduced to its fixed-interface modes below 200 Hz: the
  // ten modes below f_cut / 20 are the chain's to 2e-6 (measured: 3e-9 for the first, 1.0e-6 for
  // the tenth), and never below them (a Rayleigh-Ritz approximation from above).
  const CraigBampton cb = craig_bampton(K, M, {n - 1}, 200.0);
  CHECK(cb.interface_dofs == 1);
  CHECK(cb.fixed_interface_hz.size() > 10);
  CHECK(cb.fixed_interface_hz.maxCoeff() <= 200.0);
  const Eigen::VectorXd reduced = reduced_hz(cb);
  for (int j = 0; j < 10; ++j) {
    INFO("mode " << j + 1);
    const double exact = chain_hz(n, k, m, j + 1);
    CHECK(reduced(j) >= exact * (1 - 1e-12));
    CHECK(reduced(j) - exact <= 2e-6 * exact);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "superelement: entries in any order, and a repeated one, are read as setFromTriplets would: "
    "sorted, summed, mirrored",
    "[superelement]") {
  const auto dir = temp_dir("order");
  // The lower triangle of [4 1 0; 1 5 2; 0 2 6] scrambled, its (3, 3) given as 2 + 4.
  std::ofstream((dir / "s.mtx").string()) << "%%MatrixMarket matrix coordinate real symmetric\n"
                                             "3 3 6\n3 3 2\n3 2 2\n1 1 4\n2 2 5\n2 1 1\n3 3 4\n";
  // The upper triangle, column by column as CalculiX writes it, and then not.
  std::ofstream((dir / "a.sti").string()) << "1 1 4\n1 2 1\n2 2 5\n2 3 2\n3 3 6\n";
  std::ofstream((dir / "b.sti").string()) << "2 3 2\n3 3 6\n1 2 1\n2 2 5\n1 1 4\n";
  Eigen::Matrix3d expected;
  expected << 4, 1, 0, 1, 5, 2, 0, 2, 6;
  for (const SparseMatrix& m : {read_matrix_market((dir / "s.mtx").string()),
                                read_calculix_matrix((dir / "a.sti").string(), 3),
                                read_calculix_matrix((dir / "b.sti").string(), 3)}) {
    CHECK(m.isCompressed());
    CHECK(m.nonZeros() == 7);
    CHECK(Eigen::Matrix3d(m) == expected);
    for (int c = 0; c < 3; ++c)
      CHECK(std::is_sorted(m.innerIndexPtr() + m.outerIndexPtr()[c],
                           m.innerIndexPtr() + m.outerIndexPtr()[c + 1]));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("superelement: with every interior mode kept, Craig-Bampton is exact", "[superelement]") {
  const auto dir = temp_dir("exact");
  const int n = 40;
  write_chain(dir, n, 3e5, 0.2);
  const SparseMatrix K = read_matrix_market((dir / "K.mtx").string());
  const SparseMatrix M = read_matrix_market((dir / "M.mtx").string());
  const CraigBampton cb = craig_bampton(K, M, {n - 1, 10}, 1e9);
  REQUIRE(cb.K.rows() == n);
  const Eigen::VectorXd reduced = reduced_hz(cb);
  for (int j = 0; j < n; ++j)
    CHECK(reduced(j) == Approx(chain_hz(n, 3e5, 0.2, j + 1)).epsilon(1e-10));
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "superelement: bad files and bad reductions are refused with the file and line, or the "
    "reason",
    "[superelement]") {
  const auto dir = temp_dir("bad");
  const auto write = [&](const char* name, const std::string& text) {
    std::ofstream((dir / name).string()) << text;
    return (dir / name).string();
  };
  const auto refused = [](const auto& read, const std::string& where, const std::string& what) {
    try {
      read();
      FAIL("not refused: " << where);
    } catch (const common::InputError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(where) != std::string::npos);
      CHECK(std::string(e.what()).find(what) != std::string::npos);
    }
  };
  const std::string short_file = write("short.mtx",
                                       "%%MatrixMarket matrix coordinate real "
                                       "symmetric\n3 3 3\n1 1 2.0\n2 2 2.0\n");
  refused([&] { return read_matrix_market(short_file); }, "short.mtx:4", "ends after 2 of its 3");
  const std::string asym = write("asym.mtx",
                                 "%%MatrixMarket matrix coordinate real general\n"
                                 "2 2 3\n1 1 2.0\n1 2 1.0\n2 2 2.0\n");
  refused([&] { return read_matrix_market(asym); }, "asym.mtx", "not symmetric");
  const std::string range = write("range.mtx",
                                  "%%MatrixMarket matrix coordinate real symmetric\n"
                                  "2 2 1\n3 1 2.0\n");
  refused([&] { return read_matrix_market(range); }, "range.mtx:3", "outside the 2 rows");
  const std::string size = write("size.mtx",
                                 "%%MatrixMarket matrix coordinate real symmetric\n"
                                 "2 2 1\n1 1 2.0\n");
  refused([&] { return read_matrix_market(size, 3); }, "size.mtx:2", "the DOF map 3");
  const std::string lower = write("lower.sti", "1 1 2.0\n2 1 1.0\n");
  refused([&] { return read_calculix_matrix(lower, 2); }, "lower.sti:2", "upper triangle");
  const std::string dofs = write("bad.dof", "1.1\n1.7\n");
  refused([&] { return read_calculix_dofs(dofs); }, "bad.dof:2", "node.direction");
  const std::string text = write("text.sti", "1 1 x\n");
  refused([&] { return read_calculix_matrix(text, 2); }, "text.sti:1", "row column value");

  // A free chain (no spring to the ground) held at no interface: K_ii singular.
  SparseMatrix K(3, 3), M(3, 3);
  K.insert(0, 0) = 1;
  K.insert(0, 1) = -1;
  K.insert(1, 0) = -1;
  K.insert(1, 1) = 1;
  K.insert(2, 2) = 1;
  for (int i = 0; i < 3; ++i) M.insert(i, i) = 1;
  CHECK_THROWS_AS(craig_bampton(K, M, {2}, 10.0), std::domain_error);
  CHECK_THROWS_AS(craig_bampton(K, M, {3}, 10.0), std::invalid_argument);
  CHECK_THROWS_AS(craig_bampton(K, M, {1, 1}, 10.0), std::invalid_argument);
  // Its rigid-body mode is found by the shifted Lanczos: 0 Hz.
  const Eigen::VectorXd f = sparse_natural_frequencies_hz(K, M, 10.0, 3);
  REQUIRE(f.size() >= 1);
  CHECK(f(0) == Approx(0.0).margin(1e-6));
  std::filesystem::remove_all(dir);
}
