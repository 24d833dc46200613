// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/superelement_files.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <tuple>

#include "common/input_error.hpp"
#include "plant/superelement/node_table.hpp"
#include "plant/superelement/reduction_store.hpp"

namespace flexloop::plant::superelement {

namespace {

// A file's identity as far as a reduction depends on it: absolute path (one file however a
// process names it: a campaign's shards name it from the plan, its plan from the command line),
// size and modification time.
std::string identity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return path + "|missing";
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::weakly_canonical(path, ec);
  std::ostringstream os;
  os << (ec ? path : absolute.string()) << '|' << st.st_size << '|' << st.st_mtim.tv_sec << '.'
     << st.st_mtim.tv_nsec;
  return os.str();
}

std::string request_key(const SuperelementFiles& f) {
  std::ostringstream os;
  os.precision(17);
  os << static_cast<int>(f.format) << '\n'
     << identity(f.stiffness) << '\n'
     << identity(f.mass) << '\n'
     << identity(f.dofs) << '\n'
     << identity(f.nodes) << '\n'
     << f.modes_up_to_hz << '\n'
     << f.residual_block_solves << '\n';
  for (const long n : f.interface_nodes) os << ' ' << n;
  for (const PadRequest& pad : f.pads) {
    os << "\npad " << static_cast<int>(pad.kind);
    if (pad.within) os << " within " << pad.ball.center.transpose() << ' ' << pad.ball.radius;
    for (const long n : pad.nodes) os << ' ' << n;
  }
  return os.str();
}

// Every mesh node the request names by number: the pins, then the pads' listed nodes.
std::vector<long> named_nodes(const SuperelementFiles& f) {
  std::vector<long> out = f.interface_nodes;
  for (const PadRequest& pad : f.pads) out.insert(out.end(), pad.nodes.begin(), pad.nodes.end());
  return out;
}

// The pins' positions, in the order asked; a pin the node file lacks refused.
std::vector<Eigen::Vector3d> pin_positions(const SuperelementFiles& f, const NodeLookup& found) {
  std::vector<Eigen::Vector3d> out;
  for (const long node : f.interface_nodes) {
    const auto at = found.wanted.find(node);
    if (at == found.wanted.end())
      throw common::InputError(f.nodes, "has no node " + std::to_string(node) +
                                            " (the model names it as an interface node)");
    out.push_back(at->second);
  }
  return out;
}

// Each pad's nodes and their coordinates, as the node file has them; a mesh node in two pads or
// in a pad and a pin refused.
std::vector<PadNodes> find_pads(const SuperelementFiles& f, const NodeLookup& found) {
  std::vector<PadNodes> pads;
  std::map<long, std::size_t> owner;  // mesh node -> its pad
  const std::set<long> pins(f.interface_nodes.begin(), f.interface_nodes.end());
  std::size_t ball = 0;
  for (std::size_t k = 0; k < f.pads.size(); ++k) {
    PadNodes pad{f.pads[k].kind, {}, {}};
    const std::map<long, Eigen::Vector3d>* within =
        f.pads[k].within ? &found.within[ball++] : nullptr;
    if (within && within->empty())
      throw PadError(k, "'within' catches no node of " + f.nodes +
                            " (widen its radius, or move its center onto the body)");
    for (const long node : within ? std::vector<long>{} : f.pads[k].nodes) {
      const auto at = found.wanted.find(node);
      if (at == found.wanted.end())
        throw PadError(k, "mesh node " + std::to_string(node) + " is not in " + f.nodes);
      pad.nodes.push_back(node);
      pad.positions.push_back(at->second);
    }
    if (within)
      for (const auto& [node, x] : *within) {
        pad.nodes.push_back(node);
        pad.positions.push_back(x);
      }
    for (const long node : pad.nodes) {
      if (pins.count(node))
        throw PadError(k, "mesh node " + std::to_string(node) + " is also an 'interface' node");
      if (const auto [it, fresh] = owner.emplace(node, k); !fresh)
        throw PadError(k, "mesh node " + std::to_string(node) + " is also in pad " +
                              std::to_string(it->second + 1) + " (a node belongs to one pad)");
    }
    pads.push_back(std::move(pad));
  }
  return pads;
}

// The rows of the interface translations, node by node, x before y before z.
std::vector<Eigen::Index> interface_rows(const SuperelementFiles& f,
                                         const std::vector<DofLabel>& dofs,
                                         std::vector<DofLabel>& kept) {
  // Only the interface nodes' rows are indexed: one pass over a 10^6-row map, a few entries kept.
  const std::set<long> wanted(f.interface_nodes.begin(), f.interface_nodes.end());
  std::map<std::pair<long, int>, Eigen::Index> row_of;
  for (std::size_t r = 0; r < dofs.size(); ++r)
    if (wanted.count(dofs[r].node))
      row_of[{dofs[r].node, dofs[r].direction}] = static_cast<Eigen::Index>(r);
  std::vector<Eigen::Index> rows;
  for (const long node : f.interface_nodes) {
    const std::size_t before = rows.size();
    for (int direction = 1; direction <= 3; ++direction)
      if (const auto it = row_of.find({node, direction}); it != row_of.end()) {
        rows.push_back(it->second);
        kept.push_back({node, direction});
      }
    if (rows.size() == before)
      throw common::InputError(
          f.dofs, "has no translation of interface node " + std::to_string(node) +
                      " (a node of the mesh held in all directions by the FE tool's boundary "
                      "conditions, or not a node of this mesh: choose another interface node)");
  }
  return rows;
}

// The pads joined before the reduction (pads.hpp): (K, M) -> (T' K T, T' M T), the pins' rows
// renumbered into w, the pads' six DOFs each appended to the interface.
CraigBampton reduce_with_pads(const SparseMatrix& K, const SparseMatrix& M,
                              const std::vector<DofLabel>& dofs, std::vector<Eigen::Index> rows,
                              ReducedSuperelement& out, const SuperelementFiles& f) {
  const PadTransform t = pad_transform(dofs, out.pads);
  for (Eigen::Index& row : rows) row = t.column_of[static_cast<std::size_t>(row)];
  for (Eigen::Index c = t.first_pad_column; c < t.columns; ++c) rows.push_back(c);
  out.positions.insert(out.positions.end(), t.centroids.begin(), t.centroids.end());
  return craig_bampton(congruence(K, t), congruence(M, t), rows, f.modes_up_to_hz,
                       f.residual_block_solves);
}

std::shared_ptr<const ReducedSuperelement> read_and_reduce(const SuperelementFiles& f) {
  auto out = std::make_shared<ReducedSuperelement>();
  const std::vector<DofLabel> dofs =
      f.format == FileFormat::kCalculix ? read_calculix_dofs(f.dofs) : read_dof_csv(f.dofs);
  const auto n = static_cast<Eigen::Index>(dofs.size());
  std::vector<Ball> balls;
  for (const PadRequest& pad : f.pads)
    if (pad.within) balls.push_back(pad.ball);
  const NodeLookup where = look_up_nodes(f.nodes, named_nodes(f), balls);
  out->positions = pin_positions(f, where);
  out->pads = find_pads(f, where);
  const std::vector<Eigen::Index> rows = interface_rows(f, dofs, out->interface_dofs);
  const SparseMatrix K = f.format == FileFormat::kCalculix ? read_calculix_matrix(f.stiffness, n)
                                                           : read_matrix_market(f.stiffness, n);
  const SparseMatrix M = f.format == FileFormat::kCalculix ? read_calculix_matrix(f.mass, n)
                                                           : read_matrix_market(f.mass, n);
  out->full_dofs = n;
  out->reduction = out->pads.empty()
                       ? craig_bampton(K, M, rows, f.modes_up_to_hz, f.residual_block_solves)
                       : reduce_with_pads(K, M, dofs, rows, *out, f);
  return out;
}

}  // namespace

std::shared_ptr<const ReducedSuperelement> reduce_superelement(const SuperelementFiles& files) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const ReducedSuperelement>> done;
  const std::string key = request_key(files);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = done.find(key); it != done.end()) return it->second;
  }
  // Another process of the same campaign may have reduced it already (reduction_store.hpp).
  std::shared_ptr<const ReducedSuperelement> reduced = load_stored_reduction(key);
  if (!reduced) {
    reduced = read_and_reduce(files);
    store_reduction(key, *reduced);
  }
  const std::lock_guard<std::mutex> lock(mutex);
  return done.emplace(key, std::move(reduced)).first->second;
}

}  // namespace flexloop::plant::superelement
