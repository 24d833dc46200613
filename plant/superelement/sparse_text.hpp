// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A finite-element tool's matrices as text (issue 58): Matrix Market coordinate files and
// CalculiX's *FREQUENCY,SOLVER=MATRIXSTORAGE output (jobname.sti, .mas: "row col value" per line,
// the upper triangle, 1-based; jobname.dof: "node.direction" per row). Read streaming from a
// memory map at disk speed (std::from_chars, no iostreams), into a symmetric sparse matrix with
// both triangles stored. Every refusal names the file and line (flexloop::InputError).
// Cost: one pass over the text; memory ~ 16 bytes per entry of the file as triplets (one
// triangle), then the compressed matrix (12 bytes per stored entry, both triangles).
#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace flexloop::plant::superelement {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// A row of an FE tool's matrices: which node and which of its directions (1..6: x, y, z and the
/// rotations about them).
struct DofLabel {
  long node = 0;
  int direction = 0;
  bool operator==(const DofLabel&) const = default;
};

/// A Matrix Market file: "%%MatrixMarket matrix coordinate real|integer symmetric|general".
/// A symmetric file gives one triangle, mirrored here; a general one must be symmetric to
/// 1e-12 of its largest entry (an FE stiffness or mass matrix is). `expected_size` > 0: the
/// number of rows it must have.
SparseMatrix read_matrix_market(const std::string& path, Eigen::Index expected_size = 0);

/// A CalculiX .sti or .mas file of `size` rows: the upper triangle, mirrored here.
SparseMatrix read_calculix_matrix(const std::string& path, Eigen::Index size);

/// A CalculiX .dof file: the label of each row, in order.
std::vector<DofLabel> read_calculix_dofs(const std::string& path);

/// A CSV DOF map for Matrix Market matrices: "node,direction" per row (a header line whose first
/// field is not a number is skipped).
std::vector<DofLabel> read_dof_csv(const std::string& path);

}  // namespace flexloop::plant::superelement
