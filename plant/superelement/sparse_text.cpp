// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/sparse_text.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <tuple>
#include <utility>

#include "common/input_error.hpp"
#include "plant/superelement/mapped_text.hpp"

namespace flexloop::plant::superelement {

namespace {

using common::InputError;
using text::blank;
using text::Lines;
using text::MappedText;
using text::take;

using Triplets = std::vector<Eigen::Triplet<double, int>>;

// One "row col value" entry (1-based) into `t` (the mirror is added on compression); checks the
// range.
void add_entry(std::string_view line, Lines& lines, Eigen::Index size, bool upper_only,
               Triplets& t) {
  long r = 0, c = 0;
  double v = 0;
  if (!take(line, r) || !take(line, c) || !take(line, v) || !blank(line))
    throw lines.error("expected 'row column value'");
  if (r < 1 || c < 1 || r > size || c > size)
    throw lines.error("entry (" + std::to_string(r) + ", " + std::to_string(c) +
                      ") is outside the " + std::to_string(size) + " rows");
  if (!std::isfinite(v)) throw lines.error("the value is not a finite number");
  if (upper_only && r > c)
    throw lines.error("a lower-triangle entry: CalculiX writes the upper triangle (row <= col)");
  t.emplace_back(static_cast<int>(r - 1), static_cast<int>(c - 1), v);
}

// The compressed matrix of `t` (one triangle, mirrored when `mirror`), built in place: a count
// per column, one scatter, then each column sorted (only if it is not already: a column-major
// upper triangle, as CalculiX writes it, scatters sorted) and its repeated rows summed. Half the
// memory of storing the mirror as triplets and Eigen's setFromTriplets (its row-major copy).
SparseMatrix compressed(Eigen::Index size, const Triplets& t, bool mirror) {
  SparseMatrix m(size, size);
  std::vector<int> start(static_cast<std::size_t>(size) + 1, 0);
  for (const auto& e : t) {
    ++start[static_cast<std::size_t>(e.col()) + 1];
    if (mirror && e.row() != e.col()) ++start[static_cast<std::size_t>(e.row()) + 1];
  }
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  m.resizeNonZeros(start.back());
  std::vector<int> next(start.begin(), start.end() - 1);
  int* rows = m.innerIndexPtr();
  double* values = m.valuePtr();
  const auto put = [&](int r, int c, double v) {
    const int at = next[static_cast<std::size_t>(c)]++;
    rows[at] = r;
    values[at] = v;
  };
  for (const auto& e : t) {
    put(e.row(), e.col(), e.value());
    if (mirror && e.row() != e.col()) put(e.col(), e.row(), e.value());
  }
  // Sort and merge each column, compacting in place: `out` never passes the column's start.
  int out = 0;
  std::vector<std::pair<int, double>> column;
  for (std::size_t c = 0; c + 1 < start.size(); ++c) {
    const int begin = start[c], end = start[c + 1];
    start[c] = out;
    if (!std::is_sorted(rows + begin, rows + end)) {
      column.assign(end - begin, {});
      for (int k = begin; k < end; ++k)
        column[static_cast<std::size_t>(k - begin)] = {rows[k], values[k]};
      std::sort(column.begin(), column.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      for (int k = begin; k < end; ++k)
        std::tie(rows[k], values[k]) = column[static_cast<std::size_t>(k - begin)];
    }
    for (int k = begin; k < end; ++k) {
      if (out > start[c] && rows[out - 1] == rows[k]) {
        values[out - 1] += values[k];  // a repeated entry: summed, as setFromTriplets does
      } else {
        rows[out] = rows[k];
        values[out] = values[k];
        ++out;
      }
    }
  }
  start.back() = out;
  std::copy(start.begin(), start.end(), m.outerIndexPtr());
  m.data().resize(out);
  return m;
}

// The Matrix Market banner: whether the file stores one triangle (symmetric).
bool matrix_market_symmetric(std::string_view banner, Lines& lines) {
  std::string b(banner);
  std::transform(b.begin(), b.end(), b.begin(), [](unsigned char ch) { return std::tolower(ch); });
  if (b.rfind("%%matrixmarket matrix coordinate", 0) != 0)
    throw lines.error(
        "not a Matrix Market coordinate file (its first line must be "
        "'%%MatrixMarket matrix coordinate real symmetric')");
  if (b.find(" complex") != std::string::npos || b.find(" pattern") != std::string::npos)
    throw lines.error("the matrix must be real (or integer): an FE stiffness or mass");
  if (b.find(" symmetric") != std::string::npos) return true;
  if (b.find(" general") != std::string::npos) return false;
  throw lines.error("only 'symmetric' and 'general' matrices are read");
}

void require_symmetric(const SparseMatrix& m, const std::string& path) {
  const SparseMatrix t = m.transpose();
  const SparseMatrix d = m - t;
  double largest = 0, asymmetry = 0;
  for (int k = 0; k < m.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(m, k); it; ++it)
      largest = std::max(largest, std::abs(it.value()));
  for (int k = 0; k < d.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(d, k); it; ++it)
      asymmetry = std::max(asymmetry, std::abs(it.value()));
  if (asymmetry > 1e-12 * largest)
    throw InputError(path, "the matrix is not symmetric: |A - A^T| reaches " +
                               std::to_string(asymmetry) + " of its largest entry " +
                               std::to_string(largest) + " (an FE stiffness or mass is symmetric)");
}

}  // namespace

SparseMatrix read_matrix_market(const std::string& path, Eigen::Index expected_size) {
  const MappedText file(path);
  Lines lines(file.text(), path);
  std::string_view line;
  if (!lines.next(line)) throw lines.error("the file is empty");
  const bool symmetric = matrix_market_symmetric(line, lines);
  while (lines.next(line) && (line.starts_with("%") || blank(line))) {
  }
  long rows = 0, cols = 0, entries = 0;
  if (!take(line, rows) || !take(line, cols) || !take(line, entries) || !blank(line))
    throw lines.error("expected the size line 'rows columns entries'");
  if (rows != cols || rows < 1) throw lines.error("the matrix must be square");
  if (expected_size > 0 && rows != expected_size)
    throw lines.error("the matrix has " + std::to_string(rows) + " rows, the DOF map " +
                      std::to_string(expected_size));
  Triplets t;
  t.reserve(static_cast<std::size_t>(entries));
  long read = 0;
  while (lines.next(line)) {
    if (blank(line) || line.starts_with("%")) continue;
    if (++read > entries)
      throw lines.error("more entries than the size line's " + std::to_string(entries));
    add_entry(line, lines, rows, false, t);
  }
  if (read < entries)
    throw lines.error("the file ends after " + std::to_string(read) + " of its " +
                      std::to_string(entries) + " entries");
  SparseMatrix m = compressed(rows, t, symmetric);
  if (!symmetric) require_symmetric(m, path);
  return m;
}

SparseMatrix read_calculix_matrix(const std::string& path, Eigen::Index size) {
  const MappedText file(path);
  Lines lines(file.text(), path);
  Triplets t;
  t.reserve(static_cast<std::size_t>(file.text().size() / 24));  // 24-33 bytes a line
  std::string_view line;
  long read = 0;
  while (lines.next(line)) {
    if (blank(line)) continue;
    add_entry(line, lines, size, true, t);
    ++read;
  }
  if (read == 0) throw lines.error("no entries: the file is empty");
  return compressed(size, t, true);
}

std::vector<DofLabel> read_calculix_dofs(const std::string& path) {
  const MappedText file(path);
  Lines lines(file.text(), path);
  std::vector<DofLabel> out;
  std::string_view line;
  while (lines.next(line)) {
    if (blank(line)) continue;
    const std::size_t dot = line.find('.');
    std::string_view node = line.substr(0, dot), direction;
    if (dot != std::string_view::npos) direction = line.substr(dot + 1);
    DofLabel d;
    if (dot == std::string_view::npos || !take(node, d.node) || !blank(node) ||
        !take(direction, d.direction) || !blank(direction) || d.direction < 1 || d.direction > 6)
      throw lines.error("expected 'node.direction' (direction 1 to 6), as CalculiX writes");
    out.push_back(d);
  }
  if (out.empty()) throw lines.error("no DOFs: the file is empty");
  return out;
}

std::vector<DofLabel> read_dof_csv(const std::string& path) {
  const MappedText file(path);
  Lines lines(file.text(), path);
  std::vector<DofLabel> out;
  std::string_view line;
  bool first = true;
  while (lines.next(line)) {
    if (blank(line)) continue;
    DofLabel d;
    std::string_view rest = line;
    const bool numbers = take(rest, d.node, true) && take(rest, d.direction, true) && blank(rest);
    if (!numbers && first) {  // a header line
      first = false;
      continue;
    }
    first = false;
    if (!numbers || d.direction < 1 || d.direction > 6)
      throw lines.error("expected 'node,direction' (direction 1 to 6)");
    out.push_back(d);
  }
  if (out.empty()) throw lines.error("no DOFs: the file is empty");
  return out;
}

}  // namespace flexloop::plant::superelement
