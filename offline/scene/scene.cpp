// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/scene.hpp"

#include <filesystem>

#include <cmath>
#include <tuple>

#include "artefact/loop_schema.hpp"
#include "common/input_error.hpp"
#include "common/toml_reader.hpp"
#include "offline/scene/scene_fmu.hpp"
#include "offline/scene/scene_from_toml.hpp"

namespace flexloop::scene {

namespace {

std::vector<std::string> names(const common::TomlReader& r, const char* key) {
  std::vector<std::string> out;
  for (const auto& [s, n] : r.strings(key)) out.push_back(s);
  if (out.empty()) r.fail("'" + std::string(key) + "' must list at least one channel");
  return out;
}

double positive(const common::TomlReader& r, const char* key, double def) {
  const double v = r.number(key, def);
  if (!(v > 0) || !std::isfinite(v))
    r.fail("'" + std::string(key) + "' must be positive and finite", r.get(key));
  return v;
}

double non_negative(const common::TomlReader& r, const char* key, double def) {
  const double v = r.number(key, def);
  if (!(v >= 0)) r.fail("'" + std::string(key) + "' must not be negative", r.get(key));
  return v;
}

// A non-negative integer (seeds, bit counts, sample counts).
std::uint64_t count(const common::TomlReader& r, const char* key, std::uint64_t def) {
  const double v = r.number(key, static_cast<double>(def));
  if (!(v >= 0) || v != std::floor(v) || v > 9.007199254740992e15)
    r.fail("'" + std::string(key) + "' must be a non-negative integer", r.get(key));
  return static_cast<std::uint64_t>(v);
}

const toml::table* table(const common::TomlReader& top, const toml::table& root, const char* key,
                         bool required) {
  const auto* n = root.get(key);
  if (!n) {
    if (required) top.fail("missing [" + std::string(key) + "] table");
    return nullptr;
  }
  if (!n->as_table()) top.fail("'" + std::string(key) + "' must be a table", n);
  return n->as_table();
}

// A path in a scene is relative to the scene file's folder, so a scene moves with its files.
std::string resolved(const std::filesystem::path& base, const std::string& path) {
  return std::filesystem::path(path).is_absolute() ? path : (base / path).string();
}

void read_scene_table(const common::TomlReader& sr, const std::filesystem::path& base, Scene& s) {
  sr.allow_only({"name", "model", "description"});
  s.name = sr.string("name");
  s.model_path = resolved(base, sr.string("model"));
  if (!std::filesystem::exists(s.model_path))
    sr.fail("model file '" + s.model_path + "' does not exist", sr.get("model"));
}

// `order`, `below_hz` and `band_hz` only mean something under a `reduction`; without one they are
// refused. A reduction keeps `order` states, or (modal, modal-dc) the modes below `below_hz`.
void read_reduction(const common::TomlReader& pr, ReductionSettings& r) {
  if (!pr.has("reduction")) {
    for (const char* key : {"order", "below_hz", "band_hz"})
      if (pr.has(key))
        pr.fail("'order', 'below_hz' and 'band_hz' belong to a 'reduction'", pr.get(key));
    return;
  }
  r.method = pr.string("reduction");
  r.place = pr.place(pr.get("reduction"));
  if (r.method != "modal" && r.method != "modal-dc" && r.method != "balanced")
    pr.fail("reduction '" + r.method + "' is not one of modal, modal-dc, balanced",
            pr.get("reduction"));
  if (pr.has("order") == pr.has("below_hz"))
    pr.fail("a reduction needs either an 'order' (states to keep) or a 'below_hz' (modes kept)",
            pr.get(pr.has("order") ? "below_hz" : "reduction"));
  if (pr.has("order")) {
    r.order = static_cast<int>(count(pr, "order", 0));
    if (r.order < 1) pr.fail("'order' must be at least 1", pr.get("order"));
  } else {
    if (r.method == "balanced")
      pr.fail("'below_hz' keeps modes: it is for modal and modal-dc (balanced needs an 'order')",
              pr.get("below_hz"));
    r.below_hz = non_negative(pr, "below_hz", 0.0);
    if (!(r.below_hz > 0)) pr.fail("'below_hz' must be > 0", pr.get("below_hz"));
  }
  r.band_hz = non_negative(pr, "band_hz", 0.0);
}

void read_plant(const common::TomlReader& pr, Scene& s) {
  pr.allow_only({"gravity_preload", "disturbances", "actuators", "performance", "sensors",
                 "reduction", "order", "below_hz", "band_hz"});
  s.gravity_preload = pr.boolean("gravity_preload", false);
  s.disturbances = names(pr, "disturbances");
  s.actuators = names(pr, "actuators");
  s.performance = names(pr, "performance");
  s.sensors = names(pr, "sensors");
  read_reduction(pr, s.reduction);
}

void read_pi_controller(const common::TomlReader& cr, ControllerSettings& c) {
  cr.allow_only({"enabled", "type", "omega_d_hz", "zeta", "leak_hz", "force_limit_n"});
  c.omega_d_hz = positive(cr, "omega_d_hz", c.omega_d_hz);
  c.zeta = positive(cr, "zeta", c.zeta);
  c.leak_hz = non_negative(cr, "leak_hz", c.leak_hz);
  c.place = cr.place(cr.get("leak_hz"));
}

void read_state_space_controller(const common::TomlReader& cr, const std::filesystem::path& base,
                                 ControllerSettings& c) {
  cr.allow_only({"enabled", "type", "file", "anti_windup", "force_limit_n"});
  c.file = resolved(base, cr.string("file"));
  if (!std::filesystem::exists(c.file))
    cr.fail("controller file '" + c.file + "' does not exist", cr.get("file"));
  c.file_place = cr.place(cr.get("file"));
  c.anti_windup = cr.string("anti_windup", c.anti_windup);
  if (c.anti_windup != "hold" && c.anti_windup != "none")
    cr.fail(
        "'anti_windup' must be \"hold\" (the state holds while a command is clamped) or "
        "\"none\"",
        cr.get("anti_windup"));
  c.place = cr.place(cr.get("file"));
}

// The type decides which keys the table may hold, so it is read first; `enabled` and
// `force_limit_n` are common to all types and read after.
void read_controller(const common::TomlReader& cr, const toml::table& t,
                     const std::filesystem::path& base, Scene& s) {
  auto& c = s.controller;
  c.type = cr.string("type", c.type);
  if (c.type == "pi_force_feedback") {
    read_pi_controller(cr, c);
  } else if (c.type == "state_space") {
    read_state_space_controller(cr, base, c);
  } else if (c.type == "fmu") {
    read_fmu_controller(cr, t, base, s);
  } else if (c.type == "none") {
    cr.allow_only({"enabled", "type"});
  } else {
    cr.fail("'type' must be \"pi_force_feedback\", \"state_space\", \"fmu\" or \"none\"",
            cr.get("type"));
  }
  c.enabled = cr.boolean("enabled", c.enabled);
  if (cr.has("force_limit_n")) c.force_limit_n = positive(cr, "force_limit_n", 1.0);
  // A disabled controller is no controller: the plant runs alone.
  if (!c.enabled) c.type = "none";
}

// The PI pairs each actuator with one force sensor; refused at [plant]'s sensors, the list to fix.
void check_pi_channels(const common::TomlReader& pr, const Scene& s) {
  if (s.controller.type == "pi_force_feedback" && s.actuators.size() != s.sensors.size())
    pr.fail("PI force feedback needs one sensor per actuator (" +
                std::to_string(s.actuators.size()) + " actuators, " +
                std::to_string(s.sensors.size()) + " sensors); a state_space controller takes any",
            pr.get("sensors"));
}

void read_discretisation(const common::TomlReader& dr, DiscretisationSettings& d) {
  dr.allow_only({"method", "rate_hz", "prewarp_hz"});
  if (dr.has("method")) {
    try {
      d.method = plant::lti::parse_discretisation_method(dr.string("method"));
    } catch (const std::invalid_argument& e) {
      dr.fail(e.what(), dr.get("method"));
    }
  }
  d.rate_hz = positive(dr, "rate_hz", d.rate_hz);
  if (d.rate_hz > kMaxLoopRateHz)
    dr.fail("'rate_hz' must be at most " + std::to_string(static_cast<long>(kMaxLoopRateHz)) +
                " Hz, the loop's ceiling (as the loop commands' --rate)",
            dr.get("rate_hz"));
  d.prewarp_hz = non_negative(dr, "prewarp_hz", d.prewarp_hz);
  if (d.prewarp_hz >= d.rate_hz / 2)
    dr.fail("'prewarp_hz' must be below the Nyquist frequency rate_hz / 2", dr.get("prewarp_hz"));
}

void read_floor(const common::TomlReader& fr, FloorSettings& f) {
  fr.allow_only({"spectrum", "rms_mps2", "seed"});
  const std::string spectrum = fr.string("spectrum", artefact::to_string(f.spectrum));
  try {
    f.spectrum = artefact::parse_floor_spectrum(spectrum);
  } catch (const std::invalid_argument&) {
    fr.fail("'spectrum' must be \"white\" or a vibration criterion VC-A .. VC-E",
            fr.get("spectrum"));
  }
  if (f.spectrum != artefact::FloorSpectrum::kWhite && fr.has("rms_mps2"))
    fr.fail("'rms_mps2' is for the white spectrum; a VC curve sets its own level",
            fr.get("rms_mps2"));
  f.rms_mps2 = non_negative(fr, "rms_mps2", f.rms_mps2);
  f.seed = count(fr, "seed", f.seed);
}

void read_actuator_effect(const common::TomlReader& ar, ActuatorEffect& a) {
  ar.allow_only({"gain", "force_limit_n", "lag_s"});
  a.present = true;
  a.gain = ar.number("gain", 1.0);
  if (a.gain == 0) ar.fail("'gain' must not be zero", ar.get("gain"));
  if (!ar.has("force_limit_n")) ar.fail("missing key 'force_limit_n' (the saturation, N)");
  a.force_limit_n = positive(ar, "force_limit_n", 1.0);
  a.lag_s = non_negative(ar, "lag_s", 0.0);
}

// A force sensor and an accelerometer take the same keys, named with their unit (noise_rms_n,
// adc_range_mps2), so that a scene says the unit of every level it sets.
void read_sensor_effect(const common::TomlReader& r, const std::string& unit,
                        std::uint64_t default_seed, SensorEffect& sensor) {
  const std::string noise = "noise_rms_" + unit, range = "adc_range_" + unit;
  r.allow_only({"gain_error", noise.c_str(), "adc_bits", range.c_str(), "delay_samples", "seed"});
  sensor.present = true;
  sensor.gain_error = r.number("gain_error", 0.0);
  if (!(sensor.gain_error > -1))
    r.fail("'gain_error' must be above -1 (a relative error)", r.get("gain_error"));
  sensor.noise_rms = non_negative(r, noise.c_str(), 0.0);
  sensor.adc_bits = static_cast<int>(count(r, "adc_bits", 16));
  if (sensor.adc_bits < 1 || sensor.adc_bits > 32)
    r.fail("'adc_bits' must be 1 .. 32", r.get("adc_bits"));
  if (!r.has(range.c_str())) r.fail("missing key '" + range + "' (the ADC's full-scale span)");
  sensor.adc_range = positive(r, range.c_str(), 1.0);
  sensor.delay_samples = static_cast<int>(count(r, "delay_samples", 0));
  if (sensor.delay_samples > 32)
    r.fail("'delay_samples' must be at most 32", r.get("delay_samples"));
  sensor.seed = count(r, "seed", default_seed);
}

void read_transport_delay(const common::TomlReader& dr, EffectsSettings& e) {
  dr.allow_only({"samples"});
  e.transport_delay_samples = static_cast<int>(count(dr, "samples", 0));
  if (e.transport_delay_samples < 1 || e.transport_delay_samples > 32)
    dr.fail("'samples' must be 1 .. 32", dr.get("samples"));
  // The controller follows its own force through both delays (at most 32 samples).
  if (e.force_sensor.delay_samples + e.transport_delay_samples > 32)
    dr.fail("force-sensor delay + transport delay must be at most 32 samples", dr.get("samples"));
}

// [effects.*]: each hardware effect its own sub-table, absent when the hardware is ideal. The
// transport delay is read last: its bound counts the force sensor's delay.
void read_effects(const common::TomlReader& er, const toml::table& t, const std::string& file,
                  EffectsSettings& e) {
  er.allow_only({"actuator", "force_sensor", "accelerometer", "transport_delay"});
  if (const auto* a = table(er, t, "actuator", false))
    read_actuator_effect(common::TomlReader(*a, file, "[effects.actuator]"), e.actuator);
  for (auto [key, sensor, unit, seed] :
       {std::tuple{"force_sensor", &e.force_sensor, "n", std::uint64_t{2}},
        std::tuple{"accelerometer", &e.accelerometer, "mps2", std::uint64_t{3}}}) {
    if (const auto* st = table(er, t, key, false))
      read_sensor_effect(common::TomlReader(*st, file, "[effects." + std::string(key) + "]"), unit,
                         seed, *sensor);
  }
  if (const auto* d = table(er, t, "transport_delay", false))
    read_transport_delay(common::TomlReader(*d, file, "[effects.transport_delay]"), e);
}

void read_run(const common::TomlReader& rr, RunSettings& run) {
  rr.allow_only({"duration_s"});
  run.duration_s = positive(rr, "duration_s", run.duration_s);
}

}  // namespace

// One reader per table, in the file's documented order: with several errors the first table's
// wins. The controller is read after the plant (its checks use the channels), and the PI's
// sensor count is checked once the controller's type is known.
Scene parse_scene(const std::string& text, const std::string& file) {
  return scene_from_toml(common::parse_toml(text, file), file);
}

Scene scene_from_toml(const toml::table& root, const std::string& file) {
  Scene s;
  s.file = file;
  const auto base = std::filesystem::path(file).parent_path();
  common::TomlReader top(root, file, "scene file");
  top.allow_only({"scene", "plant", "controller", "discretisation", "floor", "effects", "run"});
  read_scene_table(common::TomlReader(*table(top, root, "scene", true), file, "[scene]"), base, s);
  const common::TomlReader pr(*table(top, root, "plant", true), file, "[plant]");
  read_plant(pr, s);
  s.controller.place = file;
  if (const auto* t = table(top, root, "controller", false))
    read_controller(common::TomlReader(*t, file, "[controller]"), *t, base, s);
  check_pi_channels(pr, s);
  if (const auto* t = table(top, root, "discretisation", false))
    read_discretisation(common::TomlReader(*t, file, "[discretisation]"), s.discretisation);
  if (const auto* t = table(top, root, "floor", false))
    read_floor(common::TomlReader(*t, file, "[floor]"), s.floor);
  if (const auto* t = table(top, root, "effects", false))
    read_effects(common::TomlReader(*t, file, "[effects]"), *t, file, s.effects);
  if (const auto* t = table(top, root, "run", false))
    read_run(common::TomlReader(*t, file, "[run]"), s.run);
  return s;
}

Scene load_scene(const std::string& path) {
  return parse_scene(common::read_input_file(path, "scene file"), path);
}

bool is_scene_file(const std::string& path) {
  try {
    const toml::table root = common::parse_toml(common::read_input_file(path, "file"), path);
    return root.contains("scene");
  } catch (const common::InputError&) {
    return false;
  }
}

}  // namespace flexloop::scene
