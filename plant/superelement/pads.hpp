// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Pads (issue 58): an interface point spread over many mesh nodes, as Nastran's RBE2 and RBE3
// spiders, so that a strut does not push on one node of a solid mesh (a point load on a solid is
// a local singularity whose stiffness depends on the mesh). Each pad gets a reference point at
// its nodes' centroid c with six DOFs v = (u_c, theta): three translations and three small
// rotations (rad). The pads enter as an exact change of coordinates u = T w of the FE body before
// Craig-Bampton, K' = T' K T, M' = T' M T, with w = (the rows kept as they are, the pads' six
// DOFs each), and the reduction keeps the six DOFs of each pad as interface:
//
//  - rigid (RBE2): every pad node follows the reference point rigidly, u_j = u_c + theta x r_j,
//    r_j = p_j - c (its rotation rows, when the mesh has them, theta). T's rows of the pad nodes
//    are those of the rigid motion: the pad is stiffened, its 6 DOFs replace its nodes' 3 n_p.
//  - distributing (RBE3): the reference point moves with the least-squares rigid fit of its
//    nodes' translations, v = W u_pad, W = (R'R)^-1 R' (R the rigid-body modes of the pad's
//    nodes, equal weights); a force and moment at the reference point reach the nodes as W' f.
//    The body is not stiffened: T replaces six of the pad's translations (chosen by pivoted QR of
//    W for a well-conditioned W_A) by v, u_A = W_A^-1 (v - W_B u_B), and keeps the others; T is
//    square and invertible, so (K', M') has the body's own eigenvalues.
//
// Equal weights: flexloop has the FE tool's matrices and its nodes' coordinates, not its
// elements, so the tributary areas an area weighting needs are not known; equal weights are
// Nastran's, ANSYS's and Abaqus's default for RBE3 / distributing coupling, and a fine, even mesh
// under the pad makes them the area weights. Sparse: T has one entry per kept row, 4 (rigid: at
// most 1 + 2 rotations) per pad translation, and 6 + 3 n_p per replaced row (distributing), so
// K' adds a dense 3 n_p x 3 n_p block per distributing pad and 6 rows per rigid one.
#include <Eigen/Dense>
#include <stdexcept>
#include <string>
#include <vector>

#include "plant/superelement/sparse_text.hpp"

namespace flexloop::plant::superelement {

enum class PadKind { kRigid, kDistributing };

/// One pad: its kind and its mesh nodes with their coordinates (m).
struct PadNodes {
  PadKind kind = PadKind::kRigid;
  std::vector<long> nodes;
  std::vector<Eigen::Vector3d> positions;
};

/// A pad that cannot be built: which one (its index among the pads asked for) and why.
class PadError : public std::invalid_argument {
 public:
  PadError(std::size_t pad, const std::string& what) : std::invalid_argument(what), pad_(pad) {}
  std::size_t pad() const { return pad_; }

 private:
  std::size_t pad_;
};

/// u = T w: the body's rows from its coordinates w = (the rows kept, in order; then six per pad:
/// x, y, z, rotation about x, y, z of its reference point). T = S + E_g G_g: S the kept rows'
/// unit entries, G_g the rows the pads replace (held here; E_g puts them in place).
struct PadTransform {
  Eigen::Index columns = 0;             ///< n' = kept rows + 6 per pad
  std::vector<Eigen::Index> column_of;  ///< per row of the body: its column in w, -1 if replaced
  std::vector<Eigen::Index> replaced_rows;  ///< the rows the pads replace, ascending
  SparseMatrix replaced;                    ///< G_g: those rows of T (replaced_rows x n')
  Eigen::Index first_pad_column = 0;        ///< pad k's DOFs are columns first + 6 k ... + 5
  std::vector<Eigen::Vector3d> centroids;   ///< each pad's reference point (m)
};

/// @throws PadError for a pad of fewer than 3 nodes, nodes on one line (its rotation about the
/// line would be free), or a pad node without its three translations in the DOF map (held by
/// the FE tool, or not a node of the mesh).
PadTransform pad_transform(const std::vector<DofLabel>& dofs, const std::vector<PadNodes>& pads);

/// T' A T for a symmetric A (both triangles stored), symmetric to the last bit: A's kept block in
/// one pass, plus the pads' terms from A's replaced columns (cost ~ one pass over A).
SparseMatrix congruence(const SparseMatrix& a, const PadTransform& t);

}  // namespace flexloop::plant::superelement
