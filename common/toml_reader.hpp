// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A small reader around a toml++ table that knows its file name and reports every problem as
// flexloop::InputError "file:line: <what>: <problem>" (model files, scene files).
#include <toml++/toml.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/input_error.hpp"
#include "common/source_ref.hpp"
#include "common/toml_text_check.hpp"

namespace flexloop::common {

class TomlReader {
 public:
  TomlReader(const toml::table& t, std::string file, std::string what)
      : t_(t), file_(std::move(file)), what_(std::move(what)) {}

  std::string place(const toml::node* n = nullptr) const {
    const auto& src = n ? n->source() : t_.source();
    return src.begin.line > 0 ? file_ + ":" + std::to_string(src.begin.line) : file_;
  }
  SourceRef source() const { return {file_, static_cast<int>(t_.source().begin.line)}; }
  [[noreturn]] void fail(const std::string& msg, const toml::node* n = nullptr) const {
    throw InputError(place(n), what_ + ": " + msg);
  }
  void allow_only(std::initializer_list<const char*> keys) const {
    for (const auto& [k, v] : t_) {
      const std::string_view key = k.str();  // clang 14 cannot capture a structured binding
      if (std::none_of(keys.begin(), keys.end(), [&](const char* a) { return key == a; })) {
        std::string list;
        for (const char* a : keys) list += (list.empty() ? "" : ", ") + std::string(a);
        fail("unknown key '" + std::string(k.str()) + "' (allowed: " + list + ")", &v);
      }
    }
  }
  const toml::node* get(const char* key) const { return t_.get(key); }
  bool has(const char* key) const { return t_.contains(key); }

  std::string string(const char* key, std::optional<std::string> def = std::nullopt) const {
    const auto* n = get(key);
    if (!n) {
      if (def) return *def;
      fail("missing key '" + std::string(key) + "'");
    }
    if (auto v = n->value<std::string>()) return *v;
    if (auto v = n->value<int64_t>()) return std::to_string(*v);  // ids may be written as numbers
    fail("'" + std::string(key) + "' must be a string", n);
  }
  double number(const char* key, std::optional<double> def = std::nullopt) const {
    const auto* n = get(key);
    if (!n) {
      if (def) return *def;
      fail("missing key '" + std::string(key) + "'");
    }
    auto v = n->value<double>();
    if (!v || !std::isfinite(*v)) fail("'" + std::string(key) + "' must be a finite number", n);
    return *v;
  }
  bool boolean(const char* key, bool def) const {
    const auto* n = get(key);
    if (!n) return def;
    auto v = n->value<bool>();
    if (!v) fail("'" + std::string(key) + "' must be true or false", n);
    return *v;
  }
  Eigen::VectorXd vector(const char* key, int size) const {
    const auto* n = get(key);
    if (!n) fail("missing key '" + std::string(key) + "'");
    return vector_of(n, key, size);
  }
  Eigen::VectorXd vector_of(const toml::node* n, const std::string& key, int size) const {
    const auto* arr = n->as_array();
    if (!arr || (size >= 0 && static_cast<int>(arr->size()) != size))
      fail("'" + key + "' must be an array of " + std::to_string(size) + " numbers", n);
    Eigen::VectorXd v(static_cast<Eigen::Index>(arr->size()));
    for (std::size_t i = 0; i < arr->size(); ++i) {
      auto d = (*arr)[i].value<double>();
      if (!d || !std::isfinite(*d))
        fail("'" + key + "' entry " + std::to_string(i + 1) + " must be a finite number", n);
      v(static_cast<Eigen::Index>(i)) = *d;
    }
    return v;
  }
  std::vector<std::pair<std::string, const toml::node*>> strings(const char* key) const {
    std::vector<std::pair<std::string, const toml::node*>> out;
    const auto* n = get(key);
    if (!n) return out;
    const auto* arr = n->as_array();
    if (!arr) fail("'" + std::string(key) + "' must be an array of strings", n);
    for (const auto& item : *arr) {
      if (auto s = item.value<std::string>())
        out.emplace_back(*s, &item);
      else if (auto i = item.value<int64_t>())
        out.emplace_back(std::to_string(*i), &item);
      else
        fail("'" + std::string(key) + "' must be an array of strings", n);
    }
    return out;
  }

 private:
  const toml::table& t_;
  std::string file_, what_;
};

/// TOML text -> table; a syntax error becomes InputError "file:line: <description>", and so
/// does text that toml++ must not see (common/toml_text_check.hpp: checked first).
inline toml::table parse_toml(const std::string& text, const std::string& file) {
  if (const auto problem = toml_text_problem(text))
    throw InputError(file + ":" + std::to_string(problem->line), problem->what);
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw InputError(file + ":" + std::to_string(e.source().begin.line),
                     std::string(e.description()));
  }
}

/// The whole file as text; InputError "path: cannot open the <what>" when it cannot be read.
inline std::string read_input_file(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open the " + what);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace flexloop::common
