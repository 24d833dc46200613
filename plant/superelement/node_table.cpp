// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/node_table.hpp"

#include <algorithm>
#include <cctype>
#include <set>
#include <string_view>

#include "common/input_error.hpp"
#include "plant/superelement/mapped_text.hpp"

namespace flexloop::plant::superelement {

namespace {

using text::blank;
using text::Lines;
using text::take;

std::string upper_without_spaces(std::string_view s) {
  std::string out;
  for (const char c : s)
    if (c != ' ' && c != '\t')
      out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

// "*NODE" or "*NODE, NSET=..." opens a node block; "*NODE PRINT", "*NODE FILE" and "*NODE
// OUTPUT" are output requests (without spaces they read "*NODEPRINT"...), not definitions.
bool opens_node_block(std::string_view keyword_line) {
  const std::string k = upper_without_spaces(keyword_line);
  return k == "*NODE" || k.starts_with("*NODE,");
}

// One "id, x[, y[, z]]" line: false when it is not one.
bool parse_node_line(std::string_view line, long& id, Eigen::Vector3d& x) {
  if (!take(line, id, true)) return false;
  x.setZero();
  for (int a = 0; a < 3; ++a) {
    if (blank(line) || line.find_first_not_of(" \t,") == std::string_view::npos) break;
    if (!take(line, x(a), true)) return false;
  }
  return line.find_first_not_of(" \t,") == std::string_view::npos;
}

// The nodes asked for by number, and those inside each ball; the rest passed over unstored.
class WantedNodes {
 public:
  WantedNodes(const std::vector<long>& wanted, const std::vector<Ball>& balls)
      : wanted_(wanted.begin(), wanted.end()), balls_(balls) {
    found_.within.resize(balls.size());
  }
  void offer(long id, const Eigen::Vector3d& x, const Lines& lines) {
    if (wanted_.count(id) && !found_.wanted.emplace(id, x).second)
      throw lines.error("node " + std::to_string(id) + " is defined twice");
    for (std::size_t b = 0; b < balls_.size(); ++b)
      if ((x - balls_[b].center).norm() <= balls_[b].radius &&
          !found_.within[b].emplace(id, x).second)
        throw lines.error("node " + std::to_string(id) + " is defined twice");
  }
  NodeLookup take_all() { return std::move(found_); }

 private:
  std::set<long> wanted_;
  std::vector<Ball> balls_;
  NodeLookup found_;
};

bool is_deck(std::string_view text) {
  Lines lines(text, "");
  std::string_view line;
  while (lines.next(line))
    if (!blank(line)) return line.find_first_not_of(" \t") == line.find('*');
  return false;
}

void read_deck(Lines& lines, WantedNodes& nodes) {
  std::string_view line;
  bool in_nodes = false;
  while (lines.next(line)) {
    if (blank(line) || line.starts_with("**")) continue;
    if (line.find_first_not_of(" \t") == line.find('*')) {
      in_nodes = opens_node_block(line);
      continue;
    }
    if (!in_nodes) continue;
    long id = 0;
    Eigen::Vector3d x;
    if (!parse_node_line(line, id, x)) throw lines.error("expected 'node, x, y, z' in *NODE");
    nodes.offer(id, x, lines);
  }
}

void read_csv(Lines& lines, WantedNodes& nodes) {
  std::string_view line;
  bool first = true;
  while (lines.next(line)) {
    if (blank(line)) continue;
    long id = 0;
    Eigen::Vector3d x;
    const bool numbers = parse_node_line(line, id, x);
    if (!numbers && first) {  // a header line
      first = false;
      continue;
    }
    first = false;
    if (!numbers) throw lines.error("expected 'id,x,y,z'");
    nodes.offer(id, x, lines);
  }
}

}  // namespace

NodeLookup look_up_nodes(const std::string& path, const std::vector<long>& wanted,
                         const std::vector<Ball>& balls) {
  const text::MappedText file(path);
  Lines lines(file.text(), path);
  WantedNodes nodes(wanted, balls);
  if (is_deck(file.text()))
    read_deck(lines, nodes);
  else
    read_csv(lines, nodes);
  return nodes.take_all();
}

std::map<long, Eigen::Vector3d> read_node_coordinates(const std::string& path,
                                                      const std::vector<long>& wanted) {
  std::map<long, Eigen::Vector3d> found = look_up_nodes(path, wanted, {}).wanted;
  for (const long id : wanted)
    if (!found.count(id))
      throw common::InputError(
          path, "has no node " + std::to_string(id) + " (the model names it as an interface node)");
  return found;
}

}  // namespace flexloop::plant::superelement
