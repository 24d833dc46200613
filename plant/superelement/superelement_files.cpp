// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/superelement_files.hpp"

#include <sys/stat.h>

#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <tuple>

#include "common/input_error.hpp"
#include "plant/superelement/node_table.hpp"

namespace flexloop::plant::superelement {

namespace {

// A file's identity as far as a reduction depends on it: path, size and modification time.
std::string identity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return path + "|missing";
  std::ostringstream os;
  os << path << '|' << st.st_size << '|' << st.st_mtim.tv_sec << '.' << st.st_mtim.tv_nsec;
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
  return os.str();
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

std::shared_ptr<const ReducedSuperelement> read_and_reduce(const SuperelementFiles& f) {
  auto out = std::make_shared<ReducedSuperelement>();
  const std::vector<DofLabel> dofs =
      f.format == FileFormat::kCalculix ? read_calculix_dofs(f.dofs) : read_dof_csv(f.dofs);
  const auto n = static_cast<Eigen::Index>(dofs.size());
  const std::map<long, Eigen::Vector3d> where = read_node_coordinates(f.nodes, f.interface_nodes);
  for (const long node : f.interface_nodes) out->positions.push_back(where.at(node));
  const std::vector<Eigen::Index> rows = interface_rows(f, dofs, out->interface_dofs);
  const SparseMatrix K = f.format == FileFormat::kCalculix ? read_calculix_matrix(f.stiffness, n)
                                                           : read_matrix_market(f.stiffness, n);
  const SparseMatrix M = f.format == FileFormat::kCalculix ? read_calculix_matrix(f.mass, n)
                                                           : read_matrix_market(f.mass, n);
  out->full_dofs = n;
  out->reduction = craig_bampton(K, M, rows, f.modes_up_to_hz, f.residual_block_solves);
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
  auto reduced = read_and_reduce(files);
  const std::lock_guard<std::mutex> lock(mutex);
  return done.emplace(key, std::move(reduced)).first->second;
}

}  // namespace flexloop::plant::superelement
