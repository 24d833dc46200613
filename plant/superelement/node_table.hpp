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

}  // namespace flexloop::plant::superelement
