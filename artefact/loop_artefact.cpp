// SPDX-License-Identifier: BSD-3-Clause
#include "artefact/loop_artefact.hpp"

#include <cmath>
#include <stdexcept>

#include "common/input_error.hpp"
#include "common/json_document.hpp"
#include "numeric/stationary_covariance.hpp"

namespace flexloop::artefact {

using nlohmann::json;

namespace {

// The longest delay in samples the effects and the PI's feedthrough removal follow.
constexpr int kMaxDelaySamples = artefact::kMaxFeedthroughDelay;

const char* const kChannelKinds[] = {"disturbances", "actuators", "performance", "sensors"};

std::vector<Channel>& kind(ChannelMap& m, int k) {
  return k == 0 ? m.disturbances : k == 1 ? m.actuators : k == 2 ? m.performance : m.sensors;
}
const std::vector<Channel>& kind(const ChannelMap& m, int k) {
  return kind(const_cast<ChannelMap&>(m), k);
}

json sensor_json(const SensorEffect& s) {
  if (!s.present) return nullptr;
  return {{"gain_error", s.gain_error},       {"noise_rms", s.noise_rms},
          {"adc_bits", s.adc_bits},           {"adc_range", s.adc_range},
          {"delay_samples", s.delay_samples}, {"seed", s.seed}};
}

json vector_json(const Eigen::VectorXd& v) {
  json out = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(v(i));
  return out;
}

std::uint64_t seed_at(const common::JsonReader& r, const std::string& key) {
  const json& v = r.get(key);
  if (!v.is_number_unsigned())
    throw common::InputError(r.place(key),
                             "expected an unsigned integer, found " + common::json_type_of(v));
  return v.get<std::uint64_t>();
}

SensorEffect read_sensor(const common::JsonReader& effects, const std::string& key) {
  SensorEffect s;
  if (!effects.has(key) || effects.get(key).is_null()) return s;
  const common::JsonReader r = effects.object(key);
  s.present = true;
  s.gain_error = r.number("gain_error");
  if (s.gain_error <= -1) throw common::InputError(r.place("gain_error"), "must be > -1");
  s.noise_rms = r.number("noise_rms");
  if (s.noise_rms < 0) throw common::InputError(r.place("noise_rms"), "must be >= 0");
  s.adc_bits = static_cast<int>(r.integer("adc_bits", 1, 53));
  s.adc_range = r.number("adc_range");
  if (s.adc_range <= 0) throw common::InputError(r.place("adc_range"), "must be > 0");
  s.delay_samples = static_cast<int>(r.integer("delay_samples", 0, kMaxDelaySamples));
  s.seed = seed_at(r, "seed");
  return s;
}

// A field that takes one of the schema's names (loop_schema.hpp), refused naming its key.
template <class Parse>
auto parse_named(const common::JsonReader& r, const std::string& key, Parse parse) {
  const std::string name = r.string(key);
  try {
    return parse(name);
  } catch (const std::invalid_argument& e) {
    throw common::InputError(r.place(key), e.what());
  }
}

void require(bool ok, const std::string& place, const std::string& what) {
  if (!ok) throw common::InputError(place, what);
}

}  // namespace

std::string to_string(ControllerKind kind) {
  switch (kind) {
    case ControllerKind::kPiForceFeedback:
      return "pi_force_feedback";
    case ControllerKind::kStateSpace:
      return "state_space";
    case ControllerKind::kFmu:
      return "fmu";
    case ControllerKind::kNone:
      break;
  }
  return "none";
}

std::vector<std::string> LoopArtefact::names(const std::vector<Channel>& kind_channels) const {
  std::vector<std::string> out;
  for (const auto& c : kind_channels) out.push_back(c.name);
  return out;
}

// Each section of the artefact has its writer and, beside it, its reader: a change to a section's
// keys is made in one place. A reader takes the sections read before it (the channel map sizes
// the plant's and the controller's matrices; the floor and the controller size the start).
namespace {

// The header: what the file is and the loop's rate and discretisation.
void read_header(const common::JsonReader& r, LoopArtefact& a) {
  require(r.string("format") == kLoopArtefactFormat, r.place("format"),
          "is not \"" + std::string(kLoopArtefactFormat) + "\"");
  const long version = r.integer("version", 0, 1 << 30);
  require(version == kLoopArtefactVersion, r.place("version"),
          "is " + std::to_string(version) + "; this flexloop reads version " +
              std::to_string(kLoopArtefactVersion) + " (rebuild it: flexloop build SCENE -o FILE)");
  a.name = r.string("name");
  a.rate_hz = r.number("rate_hz");
  require(a.rate_hz > 0, r.place("rate_hz"), "must be > 0");
  a.method = parse_named(r, "method", parse_discretisation_method);
  a.prewarp_hz = r.number("prewarp_hz");
}

json channels_json(const ChannelMap& m) {
  json channels = json::object();
  for (int k = 0; k < 4; ++k) {
    json list = json::array();
    for (const auto& c : kind(m, k)) list.push_back({{"name", c.name}, {"unit", c.unit}});
    channels[kChannelKinds[k]] = std::move(list);
  }
  return channels;
}

ChannelMap read_channels(const common::JsonReader& ch) {
  ChannelMap m;
  for (int k = 0; k < 4; ++k) {
    const json& list = ch.get(kChannelKinds[k]);
    const std::string where = ch.place(kChannelKinds[k]);
    require(list.is_array(), where,
            "expected a list of channels, found " + common::json_type_of(list));
    require(!list.empty() && list.size() <= static_cast<std::size_t>(numeric::kMaxChannels), where,
            "has " + std::to_string(list.size()) + " channels; each kind takes 1 .. " +
                std::to_string(numeric::kMaxChannels));
    for (std::size_t i = 0; i < list.size(); ++i) {
      const common::JsonReader c(list[i], where + " entry " + std::to_string(i + 1));
      kind(m, k).push_back({c.string("name"), c.string("unit")});
    }
  }
  return m;
}

json plant_json(const DiscretePlant& p) {
  json plant = {{"form", to_string(p.form)},
                {"states", p.states},
                {"spectral_radius", p.spectral_radius},
                {"A", common::matrix_to_json(p.A)},
                {"B", common::matrix_to_json(p.B)},
                {"C", common::matrix_to_json(p.C)},
                {"D", common::matrix_to_json(p.D)}};
  if (p.form == PlantForm::kModal)
    plant["modal"] = {{"Lambda_minus_I", common::matrix_to_json(p.modal.Lambda_minus_I)},
                      {"B", common::matrix_to_json(p.modal.B)},
                      {"C", common::matrix_to_json(p.modal.C)},
                      {"D", common::matrix_to_json(p.modal.D)},
                      {"T", common::matrix_to_json(p.modal.T)}};
  return plant;
}

DiscretePlant read_plant(const common::JsonReader& pl, const ChannelMap& m) {
  const std::size_t nw = m.disturbances.size(), nc = m.actuators.size(), nz = m.performance.size(),
                    ns = m.sensors.size();
  DiscretePlant p;
  p.form = parse_named(pl, "form", parse_plant_form);
  p.states = pl.labels("states");
  const std::size_t nx = p.states.size();
  require(nx >= 1, pl.place("states"), "is empty: the plant has no state");
  p.spectral_radius = pl.number("spectral_radius");
  // The matrices' sizes close over the channel map: inputs [disturbances; actuators], outputs
  // [performance; sensors].
  p.A = pl.matrix("A", nx, nx, "state", "state");
  p.B = pl.matrix("B", nx, nw + nc, "state", "input (disturbances, then actuators)");
  p.C = pl.matrix("C", nz + ns, nx, "output (performance, then sensors)", "state");
  p.D = pl.matrix("D", nz + ns, nw + nc, "output (performance, then sensors)",
                  "input (disturbances, then actuators)");
  if (p.form == PlantForm::kModal) {
    const common::JsonReader md = pl.object("modal");
    p.modal.Lambda_minus_I = md.matrix("Lambda_minus_I", nx, nx, "state", "state");
    p.modal.B = md.matrix("B", nx, nw + nc, "state", "input");
    p.modal.C = md.matrix("C", nz + ns, nx, "output", "state");
    p.modal.D = md.matrix("D", nz + ns, nw + nc, "output", "input");
    p.modal.T = md.matrix("T", nx, nx, "state", "state");
  }
  return p;
}

// The command limits of the PI and of a state-space controller: none, one for all actuators, or
// one per actuator.
void read_command_limits(const common::JsonReader& co, std::size_t nc, Eigen::VectorXd& u_min,
                         Eigen::VectorXd& u_max) {
  u_min = co.vector("u_min");
  u_max = co.vector("u_max");
  for (const auto& [key, limit] :
       {std::pair<const char*, const Eigen::VectorXd&>{"u_min", u_min}, {"u_max", u_max}}) {
    const auto n = static_cast<std::size_t>(limit.size());
    require(n == 0 || n == 1 || n == nc, co.place(key),
            "has " + std::to_string(n) + " values; expected none, one, or one per actuator (" +
                std::to_string(nc) + ")");
  }
}

void read_pi_controller(const common::JsonReader& co, const LoopArtefact& a, PiParameters& pi) {
  const std::size_t nc = a.channels.actuators.size(), ns = a.channels.sensors.size();
  require(ns == nc, co.place("type"),
          "PI force feedback needs one sensor per actuator; the channel map has " +
              std::to_string(ns) + " sensors and " + std::to_string(nc) + " actuators");
  pi.K_P = co.matrix("K_P", nc, nc, "actuator", "sensor");
  pi.K_I = co.matrix("K_I", nc, nc, "actuator", "sensor");
  pi.leak_rad_s = co.number("leak_rad_s");
  require(pi.leak_rad_s >= 0, co.place("leak_rad_s"), "must be >= 0");
  read_command_limits(co, nc, pi.u_min, pi.u_max);
  if (co.has("feedthrough"))
    pi.feedthrough = co.matrix("feedthrough", nc, nc, "sensor", "actuator");
  pi.feedthrough_delay = static_cast<int>(co.integer("feedthrough_delay", 0, kMaxDelaySamples));
  pi.dt = 1.0 / a.rate_hz;
}

void read_state_space_controller(const common::JsonReader& co, const LoopArtefact& a,
                                 StateSpaceParameters& c) {
  const std::size_t nc = a.channels.actuators.size(), ns = a.channels.sensors.size();
  const auto nxc = static_cast<std::size_t>(co.integer("states", 0, kMaxControllerStates));
  c.A = co.matrix("A", nxc, nxc, "controller state", "controller state");
  c.B = co.matrix("B", nxc, ns, "controller state", "sensor");
  c.C = co.matrix("C", nc, nxc, "actuator", "controller state");
  c.D = co.matrix("D", nc, ns, "actuator", "sensor");
  read_command_limits(co, nc, c.u_min, c.u_max);
  c.feedthrough = co.matrix("feedthrough", ns, nc, "sensor", "actuator");
  c.feedthrough_delay = static_cast<int>(co.integer("feedthrough_delay", 0, kMaxDelaySamples));
  c.anti_windup = parse_named(co, "anti_windup", parse_anti_windup);
  c.dt = 1.0 / a.rate_hz;
}

void read_fmu_controller(const common::JsonReader& co, const ChannelMap& m, FmuParameters& f) {
  const std::size_t nc = m.actuators.size(), ns = m.sensors.size();
  f.file = co.string("file");
  f.sha256 = co.string("sha256");
  const common::JsonReader parameters = co.object("parameters");
  for (const auto& [name, value] : parameters.value().items())
    f.parameters.emplace_back(name, parameters.number(name));
  f.inputs = co.labels("inputs");
  f.outputs = co.labels("outputs");
  if (co.has("max_unpacked_mb"))
    f.max_unpacked_mb = co.integer("max_unpacked_mb", 1, kMaxFmuUnpackedMb);
  require(f.inputs.size() == ns, co.place("inputs"),
          "has " + std::to_string(f.inputs.size()) + " names; expected one per sensor (" +
              std::to_string(ns) + ")");
  require(f.outputs.size() == nc, co.place("outputs"),
          "has " + std::to_string(f.outputs.size()) + " names; expected one per actuator (" +
              std::to_string(nc) + ")");
}

json controller_json(const LoopArtefact& a) {
  json controller = {{"type", to_string(a.controller)}};
  if (a.controller == ControllerKind::kPiForceFeedback) {
    controller["K_P"] = common::matrix_to_json(a.pi.K_P);
    controller["K_I"] = common::matrix_to_json(a.pi.K_I);
    controller["leak_rad_s"] = a.pi.leak_rad_s;
    controller["u_min"] = vector_json(a.pi.u_min);
    controller["u_max"] = vector_json(a.pi.u_max);
    if (a.pi.feedthrough.size() > 0)
      controller["feedthrough"] = common::matrix_to_json(a.pi.feedthrough);
    controller["feedthrough_delay"] = a.pi.feedthrough_delay;
  } else if (a.controller == ControllerKind::kStateSpace) {
    const auto& c = a.state_space;
    controller["states"] = c.A.rows();
    controller["A"] = common::matrix_to_json(c.A);
    controller["B"] = common::matrix_to_json(c.B);
    controller["C"] = common::matrix_to_json(c.C);
    controller["D"] = common::matrix_to_json(c.D);
    controller["u_min"] = vector_json(c.u_min);
    controller["u_max"] = vector_json(c.u_max);
    controller["feedthrough"] = common::matrix_to_json(c.feedthrough);
    controller["feedthrough_delay"] = c.feedthrough_delay;
    controller["anti_windup"] = to_string(c.anti_windup);
  } else if (a.controller == ControllerKind::kFmu) {
    controller["file"] = a.fmu.file;
    controller["sha256"] = a.fmu.sha256;
    json parameters = json::object();
    for (const auto& [name, value] : a.fmu.parameters) parameters[name] = value;
    controller["parameters"] = std::move(parameters);
    controller["inputs"] = a.fmu.inputs;
    controller["outputs"] = a.fmu.outputs;
    if (a.fmu.max_unpacked_mb) controller["max_unpacked_mb"] = *a.fmu.max_unpacked_mb;
  }
  return controller;
}

// The type names the controller's own reader; a check across controller and channels goes there.
void read_controller(const common::JsonReader& co, LoopArtefact& a) {
  const std::string type = co.string("type");
  if (type == "none") {
    a.controller = ControllerKind::kNone;
  } else if (type == "pi_force_feedback") {
    a.controller = ControllerKind::kPiForceFeedback;
    read_pi_controller(co, a, a.pi);
  } else if (type == "state_space") {
    a.controller = ControllerKind::kStateSpace;
    read_state_space_controller(co, a, a.state_space);
  } else if (type == "fmu") {
    a.controller = ControllerKind::kFmu;
    read_fmu_controller(co, a.channels, a.fmu);
  } else {
    throw common::InputError(
        co.place("type"),
        "is \"" + type +
            "\"; this flexloop knows \"pi_force_feedback\", \"state_space\", \"fmu\" and \"none\"");
  }
}

json floor_json(const LoopArtefact& a) {
  json floor = {{"spectrum", to_string(a.floor.spectrum)}, {"seed", a.floor.seed}};
  if (a.floor.spectrum == FloorSpectrum::kWhite)
    floor["rms_mps2"] = a.floor.rms_mps2;
  else
    floor["filter"] = {{"A", common::matrix_to_json(a.floor_filter.A)},
                       {"B", common::matrix_to_json(a.floor_filter.B)},
                       {"C", common::matrix_to_json(a.floor_filter.C)},
                       {"D", common::matrix_to_json(a.floor_filter.D)},
                       {"motion", common::matrix_to_json(a.floor_filter.motion)}};
  return floor;
}

// White floor noise has its level; a VC curve its discrete shaping filter instead.
void read_floor(const common::JsonReader& fl, LoopArtefact& a) {
  a.floor.spectrum = parse_named(fl, "spectrum", parse_floor_spectrum);
  a.floor.seed = seed_at(fl, "seed");
  if (a.floor.spectrum == FloorSpectrum::kWhite) {
    a.floor.rms_mps2 = fl.number("rms_mps2");
    require(a.floor.rms_mps2 >= 0, fl.place("rms_mps2"), "must be >= 0");
    return;
  }
  const common::JsonReader f = fl.object("filter");
  const std::size_t n = kFloorFilterOrder;
  a.floor_filter.A = f.matrix("A", n, n, "filter state", "filter state");
  a.floor_filter.B = f.matrix("B", n, 1, "filter state", "noise input");
  a.floor_filter.C = f.matrix("C", 1, n, "acceleration output", "filter state");
  a.floor_filter.D = f.matrix("D", 1, 1, "acceleration output", "noise input");
  a.floor_filter.motion = f.matrix("motion", 2, n, "velocity / displacement", "filter state");
}

json effects_json(const EffectsSettings& e) {
  json effects = {{"actuator", nullptr},
                  {"force_sensor", sensor_json(e.force_sensor)},
                  {"accelerometer", sensor_json(e.accelerometer)},
                  {"transport_delay_samples", e.transport_delay_samples}};
  if (e.actuator.present)
    effects["actuator"] = {{"gain", e.actuator.gain},
                           {"force_limit_n", e.actuator.force_limit_n},
                           {"lag_s", e.actuator.lag_s}};
  return effects;
}

// An effect written as null is ideal hardware.
EffectsSettings read_effects(const common::JsonReader& ef) {
  EffectsSettings e;
  if (!ef.get("actuator").is_null()) {
    const common::JsonReader ac = ef.object("actuator");
    e.actuator.present = true;
    e.actuator.gain = ac.number("gain");
    require(e.actuator.gain != 0, ac.place("gain"), "must not be 0");
    e.actuator.force_limit_n = ac.number("force_limit_n");
    require(e.actuator.force_limit_n > 0, ac.place("force_limit_n"), "must be > 0");
    e.actuator.lag_s = ac.number("lag_s");
    require(e.actuator.lag_s >= 0, ac.place("lag_s"), "must be >= 0");
  }
  e.force_sensor = read_sensor(ef, "force_sensor");
  e.accelerometer = read_sensor(ef, "accelerometer");
  e.transport_delay_samples =
      static_cast<int>(ef.integer("transport_delay_samples", 0, kMaxDelaySamples));
  return e;
}

json start_json(const LoopStart& start_of) {
  json start = json::object();
  for (const auto& [key, st] :
       {std::pair<const char*, const StationaryStart&>{"open_loop", start_of.open_loop},
        {"closed_loop", start_of.closed_loop}}) {
    if (!st.exists()) {
      start[key] = {{"unavailable", st.unavailable}};
      continue;
    }
    start[key] = {{"delay", st.delay},
                  {"controller_states", st.controller_states},
                  {"actuator_lag", st.actuator_lag},
                  {"note", st.note},
                  {"sensitivity", st.sensitivity},
                  {"floor_gain", common::matrix_to_json(st.floor_gain)},
                  {"covariance", common::matrix_to_json(st.covariance)}};
  }
  return start;
}

// One stationary start: why there is none, or its state covariance, whose rows follow the loop's
// state (start_rows) and the floor filter's.
void read_stationary_start(const common::JsonReader& s, const LoopArtefact& a,
                           StationaryStart& out) {
  if (s.has("unavailable")) {
    out.unavailable = s.string("unavailable");
    require(!out.unavailable.empty(), s.place("unavailable"), "must say why");
    return;
  }
  out.unavailable.clear();
  out.delay = static_cast<int>(s.integer("delay", 0, 2 * kMaxDelaySamples));
  out.controller_states = static_cast<int>(s.integer("controller_states", 0, kMaxControllerStates));
  out.actuator_lag = s.boolean("actuator_lag");
  if (s.has("note")) out.note = s.string("note");
  if (s.has("sensitivity")) {
    out.sensitivity = s.number("sensitivity");
    require(out.sensitivity >= 0, s.place("sensitivity"), "must be a number >= 0");
  }
  const auto n = static_cast<std::size_t>(start_rows(a, out));
  const std::size_t nf = a.floor.spectrum == FloorSpectrum::kWhite ? 0 : kFloorFilterOrder;
  out.floor_gain = s.matrix("floor_gain", n, nf * a.channels.disturbances.size(), "start row",
                            "floor filter state");
  out.covariance = s.matrix("covariance", n, n, "start row", "start row");
  const std::string defect = numeric::covariance_defect(out.covariance);
  require(defect.empty(), s.place("covariance"), defect);
}

// An artefact without "start" (written before starts were stored) starts at rest.
void read_start(const common::JsonReader& r, LoopArtefact& a) {
  if (!r.has("start")) {
    a.start.open_loop.unavailable = a.start.closed_loop.unavailable =
        "this artefact carries no start (rebuild it with flexloop build)";
    return;
  }
  const common::JsonReader st = r.object("start");
  read_stationary_start(st.object("open_loop"), a, a.start.open_loop);
  const common::JsonReader closed = st.object("closed_loop");
  // An FMU's state cannot be set from outside (controller/fmu/fmu_controller.hpp): a drawn
  // closed-loop start would reach it only in the loop, where nothing can refuse it.
  require(a.controller != ControllerKind::kFmu || closed.has("unavailable"), closed.place(),
          "a start with the controller's state given, but the controller is an FMU, whose "
          "state cannot be set from outside: a loop with a controller FMU starts at rest "
          "(give \"unavailable\" with the reason here, as flexloop build writes it, or "
          "rebuild the artefact with flexloop build)");
  read_stationary_start(closed, a, a.start.closed_loop);
}

json provenance_json(const Provenance& p) {
  return {{"scene", p.scene},
          {"scene_sha256", p.scene_sha256},
          {"model", p.model},
          {"model_sha256", p.model_sha256},
          {"flexloop_version", p.flexloop_version},
          {"flexloop_git", p.flexloop_git}};
}

// Provenance is for people; an artefact without it (or without a key of it) still runs.
Provenance read_provenance(const common::JsonReader& p) {
  auto text = [&p](const char* key) { return p.has(key) ? p.string(key) : std::string(); };
  return {text("scene"),        text("scene_sha256"),     text("model"),
          text("model_sha256"), text("flexloop_version"), text("flexloop_git")};
}

}  // namespace

json to_json(const LoopArtefact& a) {
  validate(a);
  return {{"format", kLoopArtefactFormat},
          {"version", kLoopArtefactVersion},
          {"name", a.name},
          {"rate_hz", a.rate_hz},
          {"method", to_string(a.method)},
          {"prewarp_hz", a.prewarp_hz},
          {"channels", channels_json(a.channels)},
          {"plant", plant_json(a.plant)},
          {"controller", controller_json(a)},
          {"floor", floor_json(a)},
          {"effects", effects_json(a.effects)},
          {"start", start_json(a.start)},
          {"run", {{"duration_s", a.duration_s}}},
          {"provenance", provenance_json(a.provenance)}};
}

// The sections in the order they were always read: with several errors the first one's wins.
LoopArtefact loop_artefact_from_json(const json& j, const std::string& place) {
  const common::JsonReader r(j, place);
  LoopArtefact a;
  a.source = place;
  read_header(r, a);
  a.channels = read_channels(r.object("channels"));
  a.plant = read_plant(r.object("plant"), a.channels);
  read_controller(r.object("controller"), a);
  read_floor(r.object("floor"), a);
  a.effects = read_effects(r.object("effects"));
  read_start(r, a);
  const common::JsonReader run = r.object("run");
  a.duration_s = run.number("duration_s");
  require(a.duration_s > 0, run.place("duration_s"), "must be > 0");
  if (r.has("provenance")) a.provenance = read_provenance(r.object("provenance"));
  return a;
}

void validate(const LoopArtefact& a) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("loop artefact: " + what);
  };
  for (int k = 0; k < 4; ++k) {
    const auto n = kind(a.channels, k).size();
    if (n < 1 || n > static_cast<std::size_t>(numeric::kMaxChannels))
      fail(std::string(kChannelKinds[k]) + ": " + std::to_string(n) +
           " channels; each kind takes 1 .. " + std::to_string(numeric::kMaxChannels));
  }
  const Eigen::Index nx = static_cast<Eigen::Index>(a.plant.states.size()),
                     nu = a.disturbances() + a.actuators(), ny = a.performance() + a.sensors();
  const auto sized = [&](const char* name, const Eigen::MatrixXd& m, Eigen::Index r,
                         Eigen::Index c) {
    if (m.rows() != r || m.cols() != c)
      fail(std::string(name) + " is " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
           ", expected " + std::to_string(r) + "x" + std::to_string(c));
    if (!m.allFinite()) fail(std::string(name) + " has an entry that is not finite");
  };
  sized("plant A", a.plant.A, nx, nx);
  sized("plant B", a.plant.B, nx, nu);
  sized("plant C", a.plant.C, ny, nx);
  sized("plant D", a.plant.D, ny, nu);
  if (a.plant.form == PlantForm::kModal) {
    sized("plant modal Lambda_minus_I", a.plant.modal.Lambda_minus_I, nx, nx);
    sized("plant modal B", a.plant.modal.B, nx, nu);
    sized("plant modal C", a.plant.modal.C, ny, nx);
    sized("plant modal D", a.plant.modal.D, ny, nu);
    sized("plant modal T", a.plant.modal.T, nx, nx);
  }
  if (!(std::isfinite(a.rate_hz) && a.rate_hz > 0)) fail("rate_hz must be finite and > 0");
  if (a.controller == ControllerKind::kPiForceFeedback && a.sensors() != a.actuators())
    fail("PI force feedback needs one sensor per actuator");
  if (a.controller == ControllerKind::kStateSpace) {
    const auto& c = a.state_space;
    const Eigen::Index nxc = c.A.rows(), ns = a.sensors(), nc = a.actuators();
    if (nxc > artefact::kMaxControllerStates)
      fail("controller: " + std::to_string(nxc) + " states; the runtime takes up to " +
           std::to_string(artefact::kMaxControllerStates));
    const auto controller_sized = [&](const char* name, const Eigen::MatrixXd& m, Eigen::Index r,
                                      Eigen::Index cols) {
      sized((std::string("controller ") + name).c_str(), m, r, cols);
    };
    controller_sized("A", c.A, nxc, nxc);
    controller_sized("B", c.B, nxc, ns);
    controller_sized("C", c.C, nc, nxc);
    controller_sized("D", c.D, nc, ns);
    controller_sized("feedthrough", c.feedthrough, ns, nc);
  }
  if (a.controller == ControllerKind::kFmu &&
      (a.fmu.file.empty() || a.fmu.inputs.size() != static_cast<std::size_t>(a.sensors()) ||
       a.fmu.outputs.size() != static_cast<std::size_t>(a.actuators())))
    fail("controller: an FMU needs its file and one variable per sensor and per actuator");
  if (a.controller == ControllerKind::kFmu && a.fmu.max_unpacked_mb &&
      (*a.fmu.max_unpacked_mb < 1 || *a.fmu.max_unpacked_mb > kMaxFmuUnpackedMb))
    fail("controller: max_unpacked_mb must be 1 .. " + std::to_string(kMaxFmuUnpackedMb));
  if (a.floor.spectrum != FloorSpectrum::kWhite && a.floor_filter.A.rows() != kFloorFilterOrder)
    fail("floor filter: expected the discrete filter of order " +
         std::to_string(kFloorFilterOrder));
  if (!(std::isfinite(a.duration_s) && a.duration_s > 0)) fail("duration_s must be finite and > 0");
}

LoopArtefact read_loop_artefact(const std::filesystem::path& file) {
  return loop_artefact_from_json(common::parse_json_file(file), file.string());
}

LoopArtefact read_loop_artefact(const std::filesystem::path& file, const LoopOverrides& o) {
  const std::string path = file.string();
  if (!is_loop_artefact_file(file))
    throw common::InputError(path,
                             "is not a loop artefact (a JSON object with \"format\": \"" +
                                 std::string(kLoopArtefactFormat) +
                                 "\"); build one from a scene: flexloop build SCENE -o LOOP.json");
  LoopArtefact a = read_loop_artefact(file);
  if (o.rate_hz > 0 && o.rate_hz != a.rate_hz)
    throw common::InputError(
        path, "key 'rate_hz': the artefact is built for " + std::to_string(a.rate_hz) +
                  " Hz; rebuild it at another rate (flexloop build SCENE --rate HZ)");
  if (o.form && *o.form != a.plant.form)
    throw common::InputError(
        path, "key 'plant': the artefact holds the " + to_string(a.plant.form) +
                  " form; rebuild it (flexloop build SCENE --form " + to_string(*o.form) + ")");
  if (o.duration_s > 0) a.duration_s = o.duration_s;
  return a;
}

void write_loop_artefact(const std::filesystem::path& file, const LoopArtefact& a) {
  const json j = to_json(a);
  // The writer checks what the reader checks (the JSON holds each double to the bit): an
  // artefact the reader would refuse is not written, and nothing is left behind.
  try {
    loop_artefact_from_json(j, file.string());
  } catch (const common::InputError& e) {
    throw std::runtime_error(std::string(e.what()) +
                             " (not written: the artefact's own reader would refuse it)");
  }
  common::write_json_atomically(
      file, j,
      {"format", "version", "name", "rate_hz", "method", "prewarp_hz", "channels", "controller",
       "floor", "effects", "run", "provenance", "plant", "form", "states", "spectral_radius",
       "name", "unit", "type"});
}

bool is_loop_artefact_file(const std::filesystem::path& file) {
  try {
    const json j = common::parse_json_file(file);
    return j.is_object() && j.value("format", std::string()) == kLoopArtefactFormat;
  } catch (const std::exception&) {
    return false;
  }
}

std::vector<FloorState> floor_states(const LoopArtefact& a) {
  std::vector<FloorState> found;
  const auto& states = a.plant.states;
  for (std::size_t c = 0; c < a.channels.disturbances.size(); ++c) {
    const std::string& name = a.channels.disturbances[c].name;
    if (name.rfind("acc:", 0) != 0) continue;
    const std::string coordinate = name.substr(4);
    for (std::size_t i = 0; i < states.size(); ++i) {
      const bool vel = states[i] == "vel:" + coordinate, pos = states[i] == "pos:" + coordinate;
      if (vel || pos)
        found.push_back({static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c), pos ? 1 : 0});
    }
  }
  return found;
}

Eigen::Index start_rows(const LoopArtefact& a, const StationaryStart& s) {
  const Eigen::Index nc = a.actuators(), ns = a.sensors();
  return static_cast<Eigen::Index>(a.plant.states.size()) + nc + s.delay * ns + (s.delay + 1) * nc +
         s.controller_states + (s.actuator_lag ? nc : 0);
}

}  // namespace flexloop::artefact
