#include "plant/lti/state_space_json.hpp"

#include "plant/lti/atomic_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <stdexcept>
#include <vector>

#include "plant/model/input_error.hpp"

namespace flexloop::plant::lti {

using nlohmann::json;

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

void put_labels(json& j, const StateSpace& s) {
  j["states"] = s.states;
  j["inputs"] = s.inputs;
  j["outputs"] = s.outputs;
}

std::string type_of(const json& v) {
  if (v.is_string()) return "string " + v.dump();
  return v.type_name();
}

// Reads one document and says where it is wrong.
class Reader {
 public:
  Reader(const json& j, std::string source) : j_(j), source_(std::move(source)) {
    if (!j_.is_object())
      throw InputError(source_, "expected a JSON object at the top level, found " + type_of(j_));
  }

  const json& get(const std::string& key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) throw InputError(place(key), "is missing");
    return *it;
  }

  bool has(const std::string& key) const { return j_.contains(key); }

  double number(const std::string& key) const { return number_at(get(key), place(key)); }

  std::string string(const std::string& key) const {
    const json& v = get(key);
    if (!v.is_string()) throw InputError(place(key), "expected a string, found " + type_of(v));
    return v.get<std::string>();
  }

  std::vector<std::string> labels(const std::string& key) const {
    const json& v = get(key);
    if (!v.is_array())
      throw InputError(place(key), "expected a list of names, found " + type_of(v));
    std::vector<std::string> out;
    std::set<std::string> seen;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string where = place(key) + " entry " + std::to_string(i + 1);
      if (!v[i].is_string()) throw InputError(where, "expected a name, found " + type_of(v[i]));
      auto name = v[i].get<std::string>();
      if (name.empty()) throw InputError(where, "is empty");
      // Duplicate names would make signal look-up by label ambiguous.
      if (!seen.insert(name).second) throw InputError(where, "duplicates the name '" + name + "'");
      out.push_back(std::move(name));
    }
    return out;
  }

  // rows x cols, each row a list of numbers; what_row / what_col name one row / column.
  Eigen::MatrixXd matrix(const std::string& key, std::size_t rows, std::size_t cols,
                         const char* what_row, const char* what_col) const {
    const json& v = get(key);
    if (!v.is_array()) throw InputError(place(key), "expected a list of rows, found " + type_of(v));
    if (v.size() != rows)
      throw InputError(place(key), "has " + std::to_string(v.size()) + " rows, expected " +
                                       std::to_string(rows) + " (one per " + what_row + ")");
    Eigen::MatrixXd m(rows, cols);
    for (std::size_t r = 0; r < rows; ++r) {
      const std::string row_place = place(key) + " row " + std::to_string(r + 1);
      const json& row = v[r];
      if (!row.is_array())
        throw InputError(row_place, "expected a list of numbers, found " + type_of(row));
      if (row.size() != cols)
        throw InputError(row_place, "has " + std::to_string(row.size()) + " entries, expected " +
                                        std::to_string(cols) + " (one per " + what_col + ")");
      for (std::size_t c = 0; c < cols; ++c)
        m(r, c) = number_at(row[c], row_place + " column " + std::to_string(c + 1));
    }
    return m;
  }

  std::string place(const std::string& key) const { return source_ + ": key '" + key + "'"; }
  const std::string& source() const { return source_; }

 private:
  static double number_at(const json& v, const std::string& where) {
    if (!v.is_number()) throw InputError(where, "expected a number, found " + type_of(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw InputError(where, "is not finite");
    return x;
  }

  const json& j_;
  std::string source_;
};

json read_provenance(const Reader& r, const json& j) {
  if (!r.has("provenance")) return nullptr;
  const json& p = j.at("provenance");
  if (!p.is_object())
    throw InputError(r.place("provenance"), "expected an object, found " + type_of(p));
  return p;
}

StateSpace read_system(const Reader& r, const char* a, const char* b, const char* c,
                       const char* d) {
  StateSpace s;
  s.states = r.labels("states");
  s.inputs = r.labels("inputs");
  s.outputs = r.labels("outputs");
  const auto nx = s.states.size(), nu = s.inputs.size(), ny = s.outputs.size();
  s.A = r.matrix(a, nx, nx, "state", "state");
  s.B = r.matrix(b, nx, nu, "state", "input");
  s.C = r.matrix(c, ny, nx, "output", "state");
  s.D = r.matrix(d, ny, nu, "output", "input");
  try {
    s.validate();  // the sizes are right by construction; this keeps the two checks in step
  } catch (const std::invalid_argument& e) {
    throw InputError(r.source(), e.what());
  }
  return s;
}

json parse_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), std::string("cannot open: ") + std::strerror(errno));
  try {
    return json::parse(in);
  } catch (const json::exception& e) {  // parse errors, and numbers that overflow a double
    throw InputError(file.string(), std::string("not valid JSON: ") + e.what());
  }
}

// One matrix row per line, each label list on one line, known keys in a fixed order, then the rest.
std::string layout(const json& j) {
  static const char* const kOrder[] = {"method", "dt",     "prewarp_hz", "spectral_radius",
                                       "states", "inputs", "outputs",    "A",
                                       "B",      "C",      "D",          "Ad",
                                       "Bd",     "Cd",     "Dd",         "provenance"};
  auto is_matrix = [](const json& v) {
    if (!v.is_array() || v.empty()) return false;
    for (const auto& row : v)
      if (!row.is_array()) return false;
    return true;
  };
  auto is_flat = [](const json& v) {
    if (!v.is_array()) return false;
    for (const auto& e : v)
      if (e.is_structured()) return false;
    return true;
  };
  auto value_text = [&](const json& v) {
    if (is_flat(v)) {  // labels: one line
      std::string text = "[";
      for (std::size_t i = 0; i < v.size(); ++i) text += (i ? ", " : "") + v[i].dump();
      return text + "]";
    }
    if (!is_matrix(v)) {
      std::string text = v.dump(2);
      std::string indented;
      for (char ch : text) {
        indented += ch;
        if (ch == '\n') indented += "  ";
      }
      return indented;
    }
    std::string text = "[";
    for (std::size_t r = 0; r < v.size(); ++r) {
      text += r ? ",\n    [" : "\n    [";
      for (std::size_t c = 0; c < v[r].size(); ++c) text += (c ? ", " : "") + v[r][c].dump();
      text += "]";
    }
    return text + "\n  ]";
  };
  std::vector<std::string> keys;
  for (const char* k : kOrder)
    if (j.contains(k)) keys.emplace_back(k);
  for (const auto& [k, v] : j.items())
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  std::string out = "{";
  for (std::size_t i = 0; i < keys.size(); ++i)
    out += (i ? ",\n  " : "\n  ") + json(keys[i]).dump() + ": " + value_text(j.at(keys[i]));
  return out + "\n}\n";
}

}  // namespace

json to_json(const StateSpace& sys, const json& provenance) {
  sys.validate();
  json j = json::object();
  put_labels(j, sys);
  j["A"] = matrix_to_json(sys.A);
  j["B"] = matrix_to_json(sys.B);
  j["C"] = matrix_to_json(sys.C);
  j["D"] = matrix_to_json(sys.D);
  if (!provenance.is_null()) j["provenance"] = provenance;
  return j;
}

json to_json(const DiscreteStateSpace& d, const json& provenance) {
  d.sys.validate();
  if (!std::isfinite(d.dt) || d.dt <= 0)
    throw std::invalid_argument("discrete state space: dt must be finite and > 0");
  json j = json::object();
  j["method"] = to_string(d.method);
  j["dt"] = d.dt;
  j["prewarp_hz"] = d.prewarp_hz;
  j["spectral_radius"] = d.spectral_radius;
  put_labels(j, d.sys);
  j["Ad"] = matrix_to_json(d.sys.A);
  j["Bd"] = matrix_to_json(d.sys.B);
  j["Cd"] = matrix_to_json(d.sys.C);
  j["Dd"] = matrix_to_json(d.sys.D);
  if (!provenance.is_null()) j["provenance"] = provenance;
  return j;
}

ContinuousArtefact continuous_from_json(const json& j, const std::string& source) {
  const Reader r(j, source);
  ContinuousArtefact out;
  out.sys = read_system(r, "A", "B", "C", "D");
  out.provenance = read_provenance(r, j);
  return out;
}

DiscreteArtefact discrete_from_json(const json& j, const std::string& source) {
  const Reader r(j, source);
  DiscreteArtefact out;
  auto& d = out.sys;
  try {
    d.method = parse_discretisation_method(r.string("method"));
  } catch (const std::invalid_argument& e) {
    throw InputError(r.place("method"), e.what());
  }
  d.dt = r.number("dt");
  if (d.dt <= 0) throw InputError(r.place("dt"), "must be > 0");
  d.prewarp_hz = r.number("prewarp_hz");
  if (d.prewarp_hz < 0) throw InputError(r.place("prewarp_hz"), "must be >= 0");
  d.spectral_radius = r.number("spectral_radius");
  d.sys = read_system(r, "Ad", "Bd", "Cd", "Dd");
  // The stated spectral radius is what users and the runtime trust; catch a hand-edited Ad.
  const double rho = spectral_radius(d.sys.A);
  if (std::abs(rho - d.spectral_radius) > 1e-9 * std::max(1.0, rho))
    throw InputError(r.place("spectral_radius"), "is " + json(d.spectral_radius).dump() +
                                                     " but Ad's is " + json(rho).dump() +
                                                     "; the file was edited or corrupted");
  out.provenance = read_provenance(r, j);
  return out;
}

ContinuousArtefact read_continuous(const std::filesystem::path& file) {
  return continuous_from_json(parse_file(file), file.string());
}

DiscreteArtefact read_discrete(const std::filesystem::path& file) {
  return discrete_from_json(parse_file(file), file.string());
}

void write_continuous(const std::filesystem::path& file, const StateSpace& sys,
                      const json& provenance) {
  write_json_atomically(file, to_json(sys, provenance));
}

void write_discrete(const std::filesystem::path& file, const DiscreteStateSpace& sys,
                    const json& provenance) {
  write_json_atomically(file, to_json(sys, provenance));
}

void write_json_atomically(const std::filesystem::path& file, const json& j) {
  write_text_atomically(file, j.is_object() ? layout(j) : j.dump(2) + "\n");
}

}  // namespace flexloop::plant::lti
