// SPDX-License-Identifier: BSD-3-Clause
// A reduction kept between processes (plant/superelement/reduction_store.hpp): what a campaign's
// plan stores, a shard reads back to the bit; a file with another key, a damaged one or one that
// ends early is not used (null: the body is reduced again), and without a store nothing is kept.
#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "plant/superelement/reduction_store.hpp"
#include "plant/superelement/superelement_files.hpp"
#include "tests/superelement/chain_files.hpp"

using namespace flexloop::plant::superelement;
using flexloop::test::temp_dir;
using flexloop::test::write_chain;
using flexloop::test::write_chain_maps;

namespace {

// The chain's reduction to its mass 40 and its modes below 300 Hz.
std::shared_ptr<const ReducedSuperelement> chain_reduction(const std::filesystem::path& dir) {
  write_chain(dir, 200, 1e6, 0.01);
  write_chain_maps(dir, 200);
  SuperelementFiles f;
  f.format = FileFormat::kMatrixMarket;
  f.stiffness = (dir / "K.mtx").string();
  f.mass = (dir / "M.mtx").string();
  f.dofs = (dir / "dofs.csv").string();
  f.nodes = (dir / "nodes.csv").string();
  f.modes_up_to_hz = 300;
  f.interface_nodes = {40};
  return reduce_superelement(f);
}

std::filesystem::path only_file(const std::filesystem::path& dir) {
  std::filesystem::path found;
  int count = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    found = e.path();
    ++count;
  }
  REQUIRE(count == 1);
  return found;
}

}  // namespace

TEST_CASE("reduction store: a stored reduction reads back to the bit under its key only") {
  const auto dir = temp_dir("store");
  const auto store = dir / "reductions";
  set_reduction_store(store.string());
  const auto reduced = chain_reduction(dir);  // stored as it is reduced
  CHECK(only_file(store).extension() == ".reduction");
  const std::string key = "an identity of the request";
  store_reduction(key, *reduced);
  const auto back = load_stored_reduction(key);
  REQUIRE(back);
  CHECK(back->reduction.K == reduced->reduction.K);
  CHECK(back->reduction.M == reduced->reduction.M);
  CHECK(back->reduction.fixed_interface_hz == reduced->reduction.fixed_interface_hz);
  CHECK(back->reduction.interface_dofs == reduced->reduction.interface_dofs);
  CHECK(back->interface_dofs == reduced->interface_dofs);
  CHECK(back->positions == reduced->positions);
  CHECK(back->full_dofs == 200);
  CHECK(back->pads.empty());
  CHECK_FALSE(load_stored_reduction("another request"));

  // Damaged: cut short by 9 bytes, the file is not used; stored again, it is.
  for (const auto& e : std::filesystem::directory_iterator(store)) {
    const auto size = std::filesystem::file_size(e.path());
    std::filesystem::resize_file(e.path(), size - 9);
  }
  CHECK_FALSE(load_stored_reduction(key));
  // Damaged counts: the body's sizes overwritten with a negative mode count and a huge size.
  store_reduction(key, *reduced);
  for (const auto& e : std::filesystem::directory_iterator(store)) {
    std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
    const std::int64_t sizes[3] = {std::int64_t{1} << 40, 3, -1};  // n, interface rows, modes
    f.seekp(static_cast<std::streamoff>(21 + 8 + 8 + key.size()));
    f.write(reinterpret_cast<const char*>(sizes), sizeof sizes);
  }
  CHECK_FALSE(load_stored_reduction(key));
  store_reduction(key, *reduced);
  CHECK(load_stored_reduction(key));
  set_reduction_store("");
  CHECK_FALSE(load_stored_reduction(key));  // no store: nothing kept
  std::filesystem::remove_all(dir);
}
