// SPDX-License-Identifier: BSD-3-Clause
#include "common/json_document.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"

namespace flexloop::common {

using nlohmann::json;

std::string json_type_of(const json& v) {
  if (v.is_string()) return "string " + v.dump();
  return v.type_name();
}

json parse_json_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), std::string("cannot open: ") + std::strerror(errno));
  try {
    return json::parse(in);
  } catch (const json::exception& e) {  // parse errors, and numbers that overflow a double
    throw InputError(file.string(), std::string("not valid JSON: ") + e.what());
  }
}

json matrix_to_json(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    json row = json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(std::move(row));
  }
  return rows;
}

namespace {

bool is_matrix(const json& v) {
  if (!v.is_array() || v.empty()) return false;
  for (const auto& row : v)
    if (!row.is_array() ||
        std::any_of(row.begin(), row.end(), [](const json& e) { return e.is_structured(); }))
      return false;
  return true;
}

bool is_flat(const json& v) {
  if (!v.is_array()) return false;
  return std::none_of(v.begin(), v.end(), [](const json& e) { return e.is_structured(); });
}

// `v` at nesting `depth` (two spaces a level): a flat list on one line, a matrix one row per
// line, an object key by key.
std::string layout(const json& v, int depth, const std::vector<std::string>& first_keys) {
  const std::string pad(static_cast<std::size_t>(2 * depth), ' ');
  const std::string inner = pad + "  ";
  if (is_flat(v)) {
    std::string text = "[";
    for (std::size_t i = 0; i < v.size(); ++i) text += (i ? ", " : "") + v[i].dump();
    return text + "]";
  }
  if (is_matrix(v)) {
    std::string text = "[";
    for (std::size_t r = 0; r < v.size(); ++r)
      text += (r ? ",\n" : "\n") + inner + layout(v[r], depth + 1, {});
    return text + "\n" + pad + "]";
  }
  if (v.is_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < v.size(); ++i)
      text += (i ? ",\n" : "\n") + inner + layout(v[i], depth + 1, {});
    return text + "\n" + pad + "]";
  }
  if (!v.is_object() || v.empty()) return v.dump();
  std::vector<std::string> keys;
  for (const auto& k : first_keys)
    if (v.contains(k)) keys.push_back(k);
  for (const auto& [k, _] : v.items())
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  std::string text = "{";
  for (std::size_t i = 0; i < keys.size(); ++i)
    text += (i ? ",\n" : "\n") + inner + json(keys[i]).dump() + ": " +
            layout(v.at(keys[i]), depth + 1, first_keys);
  return text + "\n" + pad + "}";
}

}  // namespace

void write_json_atomically(const std::filesystem::path& file, const json& j,
                           const std::vector<std::string>& first_keys) {
  write_text_atomically(file, layout(j, 0, first_keys) + "\n");
}

JsonReader::JsonReader(const json& j, std::string place) : j_(j), place_(std::move(place)) {
  if (!j_.is_object())
    throw InputError(place_, "expected a JSON object, found " + json_type_of(j_));
}

std::string JsonReader::place(const std::string& key) const {
  return place_ + ": key '" + key + "'";
}

const json& JsonReader::get(const std::string& key) const {
  const auto it = j_.find(key);
  if (it == j_.end()) throw InputError(place(key), "is missing");
  return *it;
}

JsonReader JsonReader::object(const std::string& key) const {
  const json& v = get(key);
  if (!v.is_object()) throw InputError(place(key), "expected an object, found " + json_type_of(v));
  return JsonReader(v, place_ + ": key '" + key + "'");
}

namespace {

double number_at(const json& v, const std::string& where) {
  if (!v.is_number()) throw InputError(where, "expected a number, found " + json_type_of(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw InputError(where, "is not finite");
  return x;
}

}  // namespace

double JsonReader::number(const std::string& key) const {
  return number_at(get(key), place(key));
}

long JsonReader::integer(const std::string& key, long min, long max) const {
  const json& v = get(key);
  if (!v.is_number_integer())
    throw InputError(place(key), "expected an integer, found " + json_type_of(v));
  const long x = v.get<long>();
  if (x < min || x > max)
    throw InputError(place(key), "is " + std::to_string(x) + ", must be " + std::to_string(min) +
                                     " .. " + std::to_string(max));
  return x;
}

bool JsonReader::boolean(const std::string& key) const {
  const json& v = get(key);
  if (!v.is_boolean())
    throw InputError(place(key), "expected true or false, found " + json_type_of(v));
  return v.get<bool>();
}

std::string JsonReader::string(const std::string& key) const {
  const json& v = get(key);
  if (!v.is_string()) throw InputError(place(key), "expected a string, found " + json_type_of(v));
  return v.get<std::string>();
}

std::vector<std::string> JsonReader::labels(const std::string& key) const {
  const json& v = get(key);
  if (!v.is_array())
    throw InputError(place(key), "expected a list of names, found " + json_type_of(v));
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string where = place(key) + " entry " + std::to_string(i + 1);
    if (!v[i].is_string()) throw InputError(where, "expected a name, found " + json_type_of(v[i]));
    auto name = v[i].get<std::string>();
    if (name.empty()) throw InputError(where, "is empty");
    // Duplicate names would make signal look-up by label ambiguous.
    if (!seen.insert(name).second) throw InputError(where, "duplicates the name '" + name + "'");
    out.push_back(std::move(name));
  }
  return out;
}

Eigen::MatrixXd JsonReader::matrix(const std::string& key, std::size_t rows, std::size_t cols,
                                   const char* what_row, const char* what_col) const {
  const json& v = get(key);
  if (!v.is_array())
    throw InputError(place(key), "expected a list of rows, found " + json_type_of(v));
  if (v.size() != rows)
    throw InputError(place(key), "has " + std::to_string(v.size()) + " rows, expected " +
                                     std::to_string(rows) + " (one per " + what_row + ")");
  Eigen::MatrixXd m(rows, cols);
  for (std::size_t r = 0; r < rows; ++r) {
    const std::string row_place = place(key) + " row " + std::to_string(r + 1);
    const json& row = v[r];
    if (!row.is_array())
      throw InputError(row_place, "expected a list of numbers, found " + json_type_of(row));
    if (row.size() != cols)
      throw InputError(row_place, "has " + std::to_string(row.size()) + " entries, expected " +
                                      std::to_string(cols) + " (one per " + what_col + ")");
    for (std::size_t c = 0; c < cols; ++c)
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
          number_at(row[c], row_place + " column " + std::to_string(c + 1));
  }
  return m;
}

Eigen::VectorXd JsonReader::vector(const std::string& key) const {
  const json& v = get(key);
  if (!v.is_array())
    throw InputError(place(key), "expected a list of numbers, found " + json_type_of(v));
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    out(static_cast<Eigen::Index>(i)) =
        number_at(v[i], place(key) + " entry " + std::to_string(i + 1));
  return out;
}

}  // namespace flexloop::common
