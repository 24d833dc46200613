// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/parameter_paths.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/toml_reader.hpp"
#include "offline/scene/scene_from_toml.hpp"
#include "plant/model/model_from_toml.hpp"
#include "plant/model/model_parser.hpp"

namespace flexloop::campaign {

namespace {

constexpr double kUnbounded = -std::numeric_limits<double>::infinity();

PhysicalBound at_least_zero(const std::string& what) {
  return {0.0, true, what + " must not be negative"};
}
PhysicalBound above_zero(const std::string& what) {
  return {0.0, false, what + " must be positive"};
}

// The numbers of a model element a path may name, and what each may be.
PhysicalBound element_bound(const std::string& key) {
  if (key == "stiffness" || key == "damping" || key == "mass" || key == "rho")
    return at_least_zero("an element's '" + key + "'");
  return above_zero("a section's '" + key + "'");  // E, G, A, I, Iy, Iz, J
}
const std::vector<std::string> kElementKeys = {"stiffness", "damping", "mass", "E", "G",  "A",
                                               "I",         "Iy",      "Iz",   "J", "rho"};

// The scene's tables and keys a path may name ("the PI design" for the controller).
struct SceneKey {
  const char* table;  // dotted
  const char* key;
  PhysicalBound bound;
};
const std::vector<SceneKey>& scene_keys() {
  static const std::vector<SceneKey> keys = {
      {"controller", "omega_d_hz", above_zero("the PI's omega_d_hz")},
      {"controller", "zeta", above_zero("the PI's zeta")},
      {"controller", "leak_hz", at_least_zero("the PI's leak_hz")},
      {"floor", "rms_mps2", at_least_zero("the floor's rms_mps2")},
      {"effects.actuator", "gain", above_zero("the actuator gain (it keeps its sign)")},
      {"effects.actuator", "force_limit_n", above_zero("the actuator's force_limit_n")},
      {"effects.actuator", "lag_s", at_least_zero("the actuator's lag_s")},
      {"effects.force_sensor", "gain_error", {-1.0, false, "a gain_error must be above -1"}},
      {"effects.force_sensor", "noise_rms_n", at_least_zero("a sensor noise")},
      {"effects.force_sensor", "adc_range_n", above_zero("an ADC range")},
      {"effects.accelerometer", "gain_error", {-1.0, false, "a gain_error must be above -1"}},
      {"effects.accelerometer", "noise_rms_mps2", at_least_zero("a sensor noise")},
      {"effects.accelerometer", "adc_range_mps2", above_zero("an ADC range")},
  };
  return keys;
}

std::optional<double> toml_number(const toml::node* n) {
  if (!n || !(n->is_floating_point() || n->is_integer())) return std::nullopt;
  return n->value<double>();
}

std::string toml_id(const toml::table& t) {
  const auto* n = t.get("id");
  if (!n) return "";
  if (auto s = n->value<std::string>()) return *s;
  if (auto i = n->value<int64_t>()) return std::to_string(*i);
  return "";
}

std::vector<std::string> split_path(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) out.push_back(part);
  return out;
}

// Whole-string glob: '*' matches any run of characters, everything else itself.
bool glob_match(const char* p, const char* s) {
  if (*p == '\0') return *s == '\0';
  if (*p == '*') return glob_match(p + 1, s) || (*s != '\0' && glob_match(p, s + 1));
  return *s == *p && glob_match(p + 1, s + 1);
}

// The site of a number (or of each entry of an array of numbers) at `key` of `t`.
void add_number_sites(const toml::table& t, ParameterSite site, const std::string& prefix,
                      std::vector<ParameterSite>& out) {
  const toml::node* n = t.get(site.key);
  if (const auto v = toml_number(n)) {
    site.path = prefix + site.key;
    site.nominal = *v;
    out.push_back(site);
    return;
  }
  const auto* arr = n ? n->as_array() : nullptr;
  if (!arr) return;
  for (std::size_t k = 0; k < arr->size(); ++k) {
    const auto v = toml_number(arr->get(k));
    if (!v) continue;
    ParameterSite s = site;
    s.path = prefix + site.key + "[" + std::to_string(k) + "]";
    s.entry = static_cast<int>(k);
    s.nominal = *v;
    out.push_back(s);
  }
}

}  // namespace

MachineDocuments::MachineDocuments(const std::string& scene_path)
    : MachineDocuments(common::read_input_file(scene_path, "scene file"), scene_path, "", "") {}

MachineDocuments::MachineDocuments(std::string scene_text, std::string scene_file,
                                   std::string model_text, std::string model_file)
    : scene_file_(std::move(scene_file)) {
  nominal_.scene = scene::parse_scene(scene_text, scene_file_);
  model_file_ = model_file.empty() ? nominal_.scene.model_path : model_file;
  if (model_text.empty()) model_text = common::read_input_file(model_file_, "model file");
  nominal_.model = plant::model::parse_model(model_text, model_file_);
  // Both texts passed the readers: toml++ reads them as they did.
  scene_doc_ = common::parse_toml(scene_text, scene_file_);
  model_doc_ = common::parse_toml(model_text, model_file_);
  collect_model_sites();
  collect_scene_sites();
  for (const auto& s : sites_) paths_.push_back(s.path);
}

void MachineDocuments::collect_model_sites() {
  for (const char* array : {"element", "node"}) {
    const auto* arr = model_doc_.get(array) ? model_doc_.get(array)->as_array() : nullptr;
    if (!arr) continue;
    const bool element = std::string(array) == "element";
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const auto* t = arr->get(i)->as_table();
      if (!t) continue;
      const std::string prefix = std::string(array) + "." + toml_id(*t) + ".";
      const std::vector<std::string> keys =
          element ? kElementKeys : std::vector<std::string>{"mass", "inertia"};
      for (const auto& key : keys) {
        ParameterSite site;
        site.model = true;
        site.tables = {array};
        site.item = i;
        site.key = key;
        site.bound = element ? element_bound(key) : at_least_zero("a node's '" + key + "'");
        std::vector<ParameterSite> found;
        add_number_sites(*t, site, prefix, found);
        // Products of inertia (entries 3..5 of a 3-D inertia) may have either sign.
        for (auto& s : found)
          if (key == "inertia" && s.entry >= 3) s.bound = {kUnbounded, false, ""};
        sites_.insert(sites_.end(), found.begin(), found.end());
      }
    }
  }
}

void MachineDocuments::collect_scene_sites() {
  for (const auto& k : scene_keys()) {
    const toml::table* t = &scene_doc_;
    const std::vector<std::string> tables = split_path(k.table, '.');
    for (const auto& name : tables) {
      const auto* n = t ? t->get(name) : nullptr;
      t = n ? n->as_table() : nullptr;
    }
    if (!t || !toml_number(t->get(k.key))) continue;
    ParameterSite site;
    site.model = false;
    site.tables = tables;
    site.key = k.key;
    site.bound = k.bound;
    add_number_sites(*t, site, std::string(k.table) + ".", sites_);
  }
}

const ParameterSite& MachineDocuments::site(const std::string& path) const {
  for (const auto& s : sites_)
    if (s.path == path) return s;
  throw std::out_of_range("no parameter '" + path + "'");
}

std::vector<std::string> MachineDocuments::expand(const std::string& pattern) const {
  std::vector<std::string> out;
  for (const auto& p : paths_)
    if (path_matches(pattern, p)) out.push_back(p);
  return out;
}

toml::table MachineDocuments::document(bool model, const ParameterValues& values) const {
  toml::table doc = model ? model_doc_ : scene_doc_;
  for (const auto& [path, value] : values) {
    const ParameterSite& s = site(path);
    if (s.model != model) continue;
    toml::table* t = &doc;
    for (const auto& name : s.tables) {
      toml::node* n = t->get(name);
      if (s.item != std::string::npos) n = n->as_array()->get(s.item);
      t = n->as_table();
    }
    if (s.entry < 0) {
      t->insert_or_assign(s.key, value);
    } else {
      toml::array& arr = *t->get(s.key)->as_array();
      arr.replace(arr.cbegin() + s.entry, value);
    }
  }
  return doc;
}

std::string MachineDocuments::model_text(const ParameterValues& values) const {
  return toml_text(document(true, values));
}

std::string MachineDocuments::scene_text(const ParameterValues& values) const {
  return toml_text(document(false, values));
}

Machine MachineDocuments::apply(const ParameterValues& values) const {
  bool model = false, scene = false;
  for (const auto& [path, value] : values) (site(path).model ? model : scene) = true;
  Machine m;
  // A document without drawn values is the nominal one: not read again.
  m.model =
      model ? plant::model::model_from_toml(document(true, values), model_file_) : nominal_.model;
  m.scene = scene ? scene::scene_from_toml(document(false, values), scene_file_) : nominal_.scene;
  return m;
}

std::string toml_text(const toml::table& document) {
  std::ostringstream os;
  os << document << "\n";
  return os.str();
}

bool is_model_path(const std::string& path) {
  return path.rfind("element.", 0) == 0 || path.rfind("node.", 0) == 0;
}

bool path_matches(const std::string& pattern, const std::string& path) {
  return glob_match(pattern.c_str(), path.c_str());
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::vector<std::string> nearest_names(const std::string& wrong,
                                       const std::vector<std::string>& names, std::size_t count) {
  std::vector<std::pair<std::size_t, std::string>> ranked;
  for (const auto& n : names) ranked.emplace_back(edit_distance(wrong, n), n);
  std::sort(ranked.begin(), ranked.end());
  std::vector<std::string> out;
  for (std::size_t i = 0; i < ranked.size() && i < count; ++i) out.push_back(ranked[i].second);
  return out;
}

}  // namespace flexloop::campaign
