// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/pads.hpp"

#include <Eigen/QR>

#include <array>
#include <map>

namespace flexloop::plant::superelement {

namespace {

using Triplets = std::vector<Eigen::Triplet<double, int>>;

// [r]x: [r]x w = r x w.
Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& r) {
  Eigen::Matrix3d c;
  c << 0, -r(2), r(1), r(2), 0, -r(0), -r(1), r(0), 0;
  return c;
}

// Each pad node's offset from the pad's centroid; the pad refused when its nodes cannot carry a
// rotation (fewer than three, or on one line: J = sum |r|^2 I - r r' is then singular).
std::vector<Eigen::Vector3d> offsets(const PadNodes& pad, std::size_t k,
                                     Eigen::Vector3d& centroid) {
  const std::size_t n = pad.nodes.size();
  if (n < 3)
    throw PadError(k, "has " + std::to_string(n) +
                          " mesh node(s): a pad needs 3 or more, not on one line, for its "
                          "reference point's rotations");
  centroid.setZero();
  for (const auto& p : pad.positions) centroid += p / static_cast<double>(n);
  std::vector<Eigen::Vector3d> r;
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  for (const auto& p : pad.positions) {
    r.push_back(p - centroid);
    j += r.back().squaredNorm() * Eigen::Matrix3d::Identity() - r.back() * r.back().transpose();
  }
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(j).eigenvalues();
  if (!(moments(0) > 1e-10 * moments(2)))
    throw PadError(k, "has its " + std::to_string(n) +
                          " mesh nodes on one line: its rotation about that line would be free "
                          "(add nodes off the line, or widen 'within')");
  return r;
}

// The rows of each pad node's directions 1..6 (-1 where the DOF map has none), pad by pad.
std::vector<std::vector<std::array<Eigen::Index, 6>>> pad_rows(const std::vector<DofLabel>& dofs,
                                                               const std::vector<PadNodes>& pads) {
  std::map<long, std::array<Eigen::Index, 6>> rows;
  for (const auto& pad : pads)
    for (const long node : pad.nodes) rows[node].fill(-1);
  for (std::size_t r = 0; r < dofs.size(); ++r)
    if (const auto it = rows.find(dofs[r].node);
        it != rows.end() && dofs[r].direction >= 1 && dofs[r].direction <= 6)
      it->second[static_cast<std::size_t>(dofs[r].direction - 1)] = static_cast<Eigen::Index>(r);
  std::vector<std::vector<std::array<Eigen::Index, 6>>> out(pads.size());
  for (std::size_t k = 0; k < pads.size(); ++k)
    for (const long node : pads[k].nodes) {
      const auto& node_rows = rows.at(node);
      if (node_rows[0] < 0 || node_rows[1] < 0 || node_rows[2] < 0)
        throw PadError(k, "mesh node " + std::to_string(node) +
                              " lacks a translation in the DOF map (held by the FE tool's "
                              "boundary conditions, or not a node of this mesh): leave it out");
      out[k].push_back(node_rows);
    }
  return out;
}

// Rigid: every row of the pad's nodes follows the reference point, u_j = u_c - [r_j]x theta
// (= u_c + theta x r_j); a rotation row of a node (shell or beam meshes) is theta itself.
void rigid_rows(const std::vector<Eigen::Vector3d>& r,
                const std::vector<std::array<Eigen::Index, 6>>& rows, int base, Triplets& t) {
  for (std::size_t j = 0; j < r.size(); ++j) {
    const Eigen::Matrix3d c = -cross_matrix(r[j]);
    for (int a = 0; a < 3; ++a) {
      const auto row = static_cast<int>(rows[j][static_cast<std::size_t>(a)]);
      t.emplace_back(row, base + a, 1.0);
      for (int b = 0; b < 3; ++b)
        if (c(a, b) != 0) t.emplace_back(row, base + 3 + b, c(a, b));
      if (const auto rot = rows[j][static_cast<std::size_t>(3 + a)]; rot >= 0)
        t.emplace_back(static_cast<int>(rot), base + 3 + a, 1.0);
    }
  }
}

// W = (R'R)^-1 R': the reference point's motion as the least-squares rigid fit of the pad's
// translations (column 3 j + a: node j, axis a).
Eigen::MatrixXd rigid_fit(const std::vector<Eigen::Vector3d>& r) {
  const auto n = static_cast<Eigen::Index>(r.size());
  Eigen::MatrixXd modes(3 * n, 6);
  for (Eigen::Index j = 0; j < n; ++j)
    modes.block<3, 6>(3 * j, 0) << Eigen::Matrix3d::Identity(),
        -cross_matrix(r[static_cast<std::size_t>(j)]);
  return (modes.transpose() * modes).ldlt().solve(modes.transpose());
}

// The pad's translations that the distributing pad's six DOFs replace: the first six pivots of
// W's column-pivoted QR (a well-conditioned W_A); u_A = W_A^-1 (v - W_B u_B).
std::vector<Eigen::Index> replaced_translations(const Eigen::MatrixXd& w) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(w);
  std::vector<Eigen::Index> out;
  for (Eigen::Index i = 0; i < 6; ++i) out.push_back(qr.colsPermutation().indices()(i));
  return out;
}

// The pad's translation rows as a list, column 3 j + a of W.
std::vector<Eigen::Index> translation_rows(const std::vector<std::array<Eigen::Index, 6>>& rows) {
  std::vector<Eigen::Index> out;
  for (const auto& node : rows)
    for (std::size_t a = 0; a < 3; ++a) out.push_back(node[a]);
  return out;
}

// Distributing: the replaced rows u_A = P v + Q u_B (P = W_A^-1, Q = -W_A^-1 W_B).
void distributing_rows(const std::vector<Eigen::Vector3d>& r,
                       const std::vector<std::array<Eigen::Index, 6>>& rows,
                       const std::vector<Eigen::Index>& replaced,
                       const std::vector<Eigen::Index>& column_of, int base, Triplets& t) {
  const Eigen::MatrixXd w = rigid_fit(r);
  const std::vector<Eigen::Index> all = translation_rows(rows);
  std::vector<bool> is_replaced(all.size(), false);
  Eigen::MatrixXd wa(6, 6);
  for (std::size_t i = 0; i < 6; ++i) {
    wa.col(static_cast<Eigen::Index>(i)) = w.col(replaced[i]);
    is_replaced[static_cast<std::size_t>(replaced[i])] = true;
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(wa);
  const Eigen::MatrixXd p = lu.inverse(), q = -lu.solve(w);  // q's columns A: unused
  for (Eigen::Index i = 0; i < 6; ++i) {
    const auto row =
        static_cast<int>(all[static_cast<std::size_t>(replaced[static_cast<std::size_t>(i)])]);
    for (int c = 0; c < 6; ++c) t.emplace_back(row, base + c, p(i, c));
    for (std::size_t b = 0; b < all.size(); ++b)
      if (!is_replaced[b] && q(i, static_cast<Eigen::Index>(b)) != 0)
        t.emplace_back(row, static_cast<int>(column_of[static_cast<std::size_t>(all[b])]),
                       q(i, static_cast<Eigen::Index>(b)));
  }
}

// The rows each pad replaces (rigid: every row of its nodes; distributing: six translations),
// marked in `gone`; each pad's node offsets, its centroid, and a distributing pad's choice.
void mark_replaced_rows(const std::vector<PadNodes>& pads,
                        const std::vector<std::vector<std::array<Eigen::Index, 6>>>& rows,
                        std::vector<std::vector<Eigen::Vector3d>>& r,
                        std::vector<std::vector<Eigen::Index>>& replaced, PadTransform& out,
                        std::vector<bool>& gone) {
  for (std::size_t k = 0; k < pads.size(); ++k) {
    r[k] = offsets(pads[k], k, out.centroids[k]);
    if (pads[k].kind == PadKind::kRigid) {
      for (const auto& node : rows[k])
        for (const Eigen::Index row : node)
          if (row >= 0) gone[static_cast<std::size_t>(row)] = true;
    } else {
      const std::vector<Eigen::Index> all = translation_rows(rows[k]);
      for (const Eigen::Index i : replaced_translations(rigid_fit(r[k]))) {
        replaced[k].push_back(i);
        gone[static_cast<std::size_t>(all[static_cast<std::size_t>(i)])] = true;
      }
    }
  }
}

// K restricted to the kept rows and columns, renumbered into w (n' x n', pad columns empty):
// one pass, in place (column_of keeps the rows' order, so each insert appends).
SparseMatrix kept_block(const SparseMatrix& a, const std::vector<Eigen::Index>& column_of,
                        Eigen::Index columns) {
  Eigen::VectorXi count = Eigen::VectorXi::Zero(columns);
  for (int c = 0; c < a.outerSize(); ++c)
    if (const Eigen::Index bc = column_of[static_cast<std::size_t>(c)]; bc >= 0)
      for (SparseMatrix::InnerIterator it(a, c); it; ++it)
        count(bc) += column_of[static_cast<std::size_t>(it.row())] >= 0;
  SparseMatrix b(columns, columns);
  b.reserve(count);
  for (int c = 0; c < a.outerSize(); ++c)
    if (const Eigen::Index bc = column_of[static_cast<std::size_t>(c)]; bc >= 0)
      for (SparseMatrix::InnerIterator it(a, c); it; ++it)
        if (const Eigen::Index r = column_of[static_cast<std::size_t>(it.row())]; r >= 0)
          b.insert(r, bc) = it.value();
  b.makeCompressed();
  return b;
}

// The columns `cols` of A (all rows): A E_g.
SparseMatrix columns_of(const SparseMatrix& a, const std::vector<Eigen::Index>& cols) {
  Triplets t;
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (SparseMatrix::InnerIterator it(a, static_cast<Eigen::Index>(cols[j])); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), static_cast<int>(j), it.value());
  SparseMatrix out(a.rows(), static_cast<Eigen::Index>(cols.size()));
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

}  // namespace

PadTransform pad_transform(const std::vector<DofLabel>& dofs, const std::vector<PadNodes>& pads) {
  const auto n = static_cast<Eigen::Index>(dofs.size());
  const auto rows = pad_rows(dofs, pads);
  std::vector<std::vector<Eigen::Vector3d>> r(pads.size());
  std::vector<std::vector<Eigen::Index>> replaced(pads.size());
  PadTransform out;
  out.centroids.resize(pads.size());
  std::vector<bool> gone(static_cast<std::size_t>(n), false);
  mark_replaced_rows(pads, rows, r, replaced, out, gone);
  out.column_of.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> replaced_index(static_cast<std::size_t>(n), -1);
  for (Eigen::Index row = 0; row < n; ++row)
    if (gone[static_cast<std::size_t>(row)]) {
      replaced_index[static_cast<std::size_t>(row)] = static_cast<int>(out.replaced_rows.size());
      out.replaced_rows.push_back(row);
    } else {
      out.column_of[static_cast<std::size_t>(row)] = out.first_pad_column++;
    }
  Triplets t;
  for (std::size_t k = 0; k < pads.size(); ++k) {
    const int base = static_cast<int>(out.first_pad_column + 6 * static_cast<Eigen::Index>(k));
    if (pads[k].kind == PadKind::kRigid)
      rigid_rows(r[k], rows[k], base, t);
    else
      distributing_rows(r[k], rows[k], replaced[k], out.column_of, base, t);
  }
  for (auto& entry : t)  // full rows -> rows of G_g
    entry = {replaced_index[static_cast<std::size_t>(entry.row())], entry.col(), entry.value()};
  out.columns = out.first_pad_column + 6 * static_cast<Eigen::Index>(pads.size());
  out.replaced.resize(static_cast<Eigen::Index>(out.replaced_rows.size()), out.columns);
  out.replaced.setFromTriplets(t.begin(), t.end());
  return out;
}

SparseMatrix congruence(const SparseMatrix& a, const PadTransform& t) {
  // T = S + E_g G_g: T' A T = S'AS + S'X + (S'X)' + G_g' E_g' X, X = (A E_g) G_g (n x n', its
  // rows the neighbours of the replaced rows: small). S'AS is A's kept block, in one pass.
  const SparseMatrix x = columns_of(a, t.replaced_rows) * t.replaced;
  std::vector<int> replaced_index(t.column_of.size(), -1);
  for (std::size_t i = 0; i < t.replaced_rows.size(); ++i)
    replaced_index[static_cast<std::size_t>(t.replaced_rows[i])] = static_cast<int>(i);
  Triplets kept_rows, gone_rows;
  for (int c = 0; c < x.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(x, c); it; ++it) {
      const auto row = static_cast<std::size_t>(it.row());
      if (t.column_of[row] >= 0)
        kept_rows.emplace_back(static_cast<int>(t.column_of[row]), c, it.value());
      else
        gone_rows.emplace_back(replaced_index[row], c, it.value());
    }
  SparseMatrix sx(t.columns, t.columns), ex(t.replaced.rows(), t.columns);
  sx.setFromTriplets(kept_rows.begin(), kept_rows.end());
  ex.setFromTriplets(gone_rows.begin(), gone_rows.end());
  const SparseMatrix d = SparseMatrix(t.replaced.transpose()) * ex;
  const SparseMatrix sx_t = sx.transpose(), d_t = d.transpose();
  SparseMatrix out = kept_block(a, t.column_of, t.columns) + sx + sx_t + 0.5 * (d + d_t);
  out.makeCompressed();
  return out;
}

}  // namespace flexloop::plant::superelement
