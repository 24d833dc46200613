#include "tools/scene/scene.hpp"

#include <filesystem>

#include "plant/model/input_error.hpp"
#include "plant/model/toml_reader.hpp"

namespace flexloop::scene {

namespace {

using plant::model::TomlReader;

std::vector<std::string> names(const TomlReader& r, const char* key) {
  std::vector<std::string> out;
  for (const auto& [s, n] : r.strings(key)) out.push_back(s);
  if (out.empty()) r.fail("'" + std::string(key) + "' must list at least one channel");
  return out;
}

double positive(const TomlReader& r, const char* key, double def) {
  const double v = r.number(key, def);
  if (!(v > 0)) r.fail("'" + std::string(key) + "' must be positive", r.get(key));
  return v;
}

double non_negative(const TomlReader& r, const char* key, double def) {
  const double v = r.number(key, def);
  if (!(v >= 0)) r.fail("'" + std::string(key) + "' must not be negative", r.get(key));
  return v;
}

const toml::table* table(const TomlReader& top, const toml::table& root, const char* key,
                         bool required) {
  const auto* n = root.get(key);
  if (!n) {
    if (required) top.fail("missing [" + std::string(key) + "] table");
    return nullptr;
  }
  if (!n->as_table()) top.fail("'" + std::string(key) + "' must be a table", n);
  return n->as_table();
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file) {
  const toml::table root = plant::model::parse_toml(text, file);
  Scene s;
  s.file = file;
  TomlReader top(root, file, "scene file");
  top.allow_only({"scene", "plant", "controller", "discretisation", "floor", "run"});

  TomlReader sr(*table(top, root, "scene", true), file, "[scene]");
  sr.allow_only({"name", "model", "description"});
  s.name = sr.string("name");
  const std::string model = sr.string("model");
  const auto base = std::filesystem::path(file).parent_path();
  s.model_path = std::filesystem::path(model).is_absolute() ? model : (base / model).string();
  if (!std::filesystem::exists(s.model_path))
    sr.fail("model file '" + s.model_path + "' does not exist", sr.get("model"));

  TomlReader pr(*table(top, root, "plant", true), file, "[plant]");
  pr.allow_only({"gravity_preload", "disturbances", "actuators", "performance", "sensors"});
  s.gravity_preload = pr.boolean("gravity_preload", false);
  s.disturbances = names(pr, "disturbances");
  s.actuators = names(pr, "actuators");
  s.performance = names(pr, "performance");
  s.sensors = names(pr, "sensors");
  if (s.actuators.size() != s.sensors.size())
    pr.fail("force feedback needs one sensor per actuator (" + std::to_string(s.actuators.size()) +
                " actuators, " + std::to_string(s.sensors.size()) + " sensors)",
            pr.get("sensors"));

  if (const auto* t = table(top, root, "controller", false)) {
    TomlReader cr(*t, file, "[controller]");
    cr.allow_only({"enabled", "type", "omega_d_hz", "zeta", "leak_hz", "force_limit_n"});
    if (cr.string("type", std::string("pi_force_feedback")) != "pi_force_feedback")
      cr.fail("'type' must be \"pi_force_feedback\" (the only controller so far)", cr.get("type"));
    auto& c = s.controller;
    c.enabled = cr.boolean("enabled", c.enabled);
    c.omega_d_hz = positive(cr, "omega_d_hz", c.omega_d_hz);
    c.zeta = positive(cr, "zeta", c.zeta);
    c.leak_hz = non_negative(cr, "leak_hz", c.leak_hz);
    if (cr.has("force_limit_n")) c.force_limit_n = positive(cr, "force_limit_n", 1.0);
  }

  if (const auto* t = table(top, root, "discretisation", false)) {
    TomlReader dr(*t, file, "[discretisation]");
    dr.allow_only({"method", "rate_hz", "prewarp_hz"});
    auto& d = s.discretisation;
    if (dr.has("method")) {
      try {
        d.method = plant::lti::parse_discretisation_method(dr.string("method"));
      } catch (const std::invalid_argument& e) {
        dr.fail(e.what(), dr.get("method"));
      }
    }
    d.rate_hz = positive(dr, "rate_hz", d.rate_hz);
    d.prewarp_hz = non_negative(dr, "prewarp_hz", d.prewarp_hz);
    if (d.prewarp_hz >= d.rate_hz / 2)
      dr.fail("'prewarp_hz' must be below the Nyquist frequency rate_hz / 2", dr.get("prewarp_hz"));
  }

  if (const auto* t = table(top, root, "floor", false)) {
    TomlReader fr(*t, file, "[floor]");
    fr.allow_only({"spectrum", "rms_mps2", "seed"});
    auto& f = s.floor;
    f.spectrum = fr.string("spectrum", f.spectrum);
    if (f.spectrum != "white")
      fr.fail("'spectrum' must be \"white\" (band-limited white floor acceleration)",
              fr.get("spectrum"));
    f.rms_mps2 = non_negative(fr, "rms_mps2", f.rms_mps2);
    const double seed = non_negative(fr, "seed", 1.0);
    if (seed != std::floor(seed) || seed > 9.007199254740992e15)
      fr.fail("'seed' must be a non-negative integer", fr.get("seed"));
    f.seed = static_cast<std::uint64_t>(seed);
  }

  if (const auto* t = table(top, root, "run", false)) {
    TomlReader rr(*t, file, "[run]");
    rr.allow_only({"duration_s"});
    s.run.duration_s = positive(rr, "duration_s", s.run.duration_s);
  }
  return s;
}

Scene load_scene(const std::string& path) {
  return parse_scene(plant::model::read_input_file(path, "scene file"), path);
}

bool is_scene_file(const std::string& path) {
  try {
    const toml::table root = toml::parse_file(path);
    return root.contains("scene");
  } catch (const toml::parse_error&) {
    return false;
  }
}

}  // namespace flexloop::scene
