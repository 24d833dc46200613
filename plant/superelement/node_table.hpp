// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Where a superelement's mesh nodes are (issue 58): the coordinates of the nodes a model names as
// its interface, read from the FE tool's own input deck or from a CSV table.
#include <Eigen/Dense>
#include <map>
#include <string>
#include <vector>

namespace flexloop::plant::superelement {

/// The coordinates (m) of the mesh nodes `wanted`, read from `path`: either a CalculiX / Abaqus
/// input deck, whose *NODE blocks hold "id, x, y, z" (missing trailing coordinates are 0, as
/// Abaqus reads them; *INCLUDE is not followed), or a CSV table "id,x,y,z" (a header line whose
/// first field is not a number is skipped). Nodes not wanted are passed over unstored, so a
/// 10^6-node deck costs one pass and no memory.
/// @throws common::InputError naming file:line for a malformed node line or a node given twice,
/// and the file and the node for a wanted node the file does not have.
std::map<long, Eigen::Vector3d> read_node_coordinates(const std::string& path,
                                                      const std::vector<long>& wanted);

/// A ball of space: the nodes a pad's `within` catches (|x - center| <= radius).
struct Ball {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0;
};

struct NodeLookup {
  std::map<long, Eigen::Vector3d> wanted;               ///< every wanted node
  std::vector<std::map<long, Eigen::Vector3d>> within;  ///< per ball, the nodes inside (maybe none)
};

/// The wanted nodes the file has (those it lacks are left out, for the caller to name), and in
/// the same pass the nodes inside each of `balls`. @throws common::InputError naming file:line for
/// a malformed node line or a node given twice.
NodeLookup look_up_nodes(const std::string& path, const std::vector<long>& wanted,
                         const std::vector<Ball>& balls);

}  // namespace flexloop::plant::superelement
