// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A superelement as a model file names it (issue 58): the FE tool's files (stiffness, mass, DOF
// map, node coordinates), the interface nodes and the cut-off, read and reduced by Craig-Bampton
// into what the model joins. A reduction is remembered per process, keyed by the files' identity
// (path, size, modification time) and the request: a campaign that re-reads the model for each
// sample reduces the body once.
#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "plant/superelement/craig_bampton.hpp"
#include "plant/superelement/node_table.hpp"
#include "plant/superelement/pads.hpp"
#include "plant/superelement/sparse_text.hpp"

namespace flexloop::plant::superelement {

enum class FileFormat { kCalculix, kMatrixMarket };

/// A pad as a model file asks for it (pads.hpp): its mesh nodes by number, or every node of the
/// mesh inside a ball.
struct PadRequest {
  PadKind kind = PadKind::kRigid;
  std::vector<long> nodes;  // when not `within`
  bool within = false;
  Ball ball;  // when `within`
};

struct SuperelementFiles {
  FileFormat format = FileFormat::kCalculix;
  std::string stiffness, mass, dofs, nodes;  // paths as they are to be opened
  double modes_up_to_hz = 0;
  std::vector<long> interface_nodes;  // mesh node numbers (one-node interfaces: pins)
  std::vector<PadRequest> pads;
  int residual_block_solves = 0;  // the unkept modes' moments (residual_moments.hpp); 0: none
};

struct ReducedSuperelement {
  // Interface rows first: the pins' translations in interface_dofs' order, then six per pad
  // (x, y, z and the rotations about x, y, z of its reference point, rad), then the modes.
  CraigBampton reduction;
  std::vector<DofLabel> interface_dofs;    // the pins' kept translations (directions 1..3)
  std::vector<Eigen::Vector3d> positions;  // per pin, in the order asked, then per pad (m)
  std::vector<PadNodes> pads;              // each pad's mesh nodes, as found
  Eigen::Index full_dofs = 0;              // rows of the FE tool's K and M
};

/// Reads and reduces (or returns the process's earlier reduction of the same files and request).
/// An interface node keeps the translations the DOF map has for it; its rotations, if any, are
/// interior (the interface is a pin). @throws common::InputError naming the file (and line) for
/// bad files, an interface node without translations in the DOF map, or a cut-off below the
/// first fixed-interface mode; PadError naming the pad (pads.hpp, and a `within` that catches no
/// node, a mesh node in two pads or in a pad and a pin); std::domain_error from the reduction
/// (craig_bampton.hpp).
std::shared_ptr<const ReducedSuperelement> reduce_superelement(const SuperelementFiles& files);

}  // namespace flexloop::plant::superelement
