// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/state_space_json.hpp"

#include "common/json_document.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <stdexcept>
#include <vector>

#include "common/input_error.hpp"

namespace flexloop::plant::lti {

using nlohmann::json;

namespace {

void put_labels(json& j, const StateSpace& s) {
  j["states"] = s.states;
  j["inputs"] = s.inputs;
  j["outputs"] = s.outputs;
}

using Reader = common::JsonReader;

json read_provenance(const Reader& r, const json& j) {
  if (!r.has("provenance")) return nullptr;
  const json& p = j.at("provenance");
  if (!p.is_object())
    throw common::InputError(r.place("provenance"),
                             "expected an object, found " + common::json_type_of(p));
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
    throw common::InputError(r.place(), e.what());
  }
  return s;
}

}  // namespace

json to_json(const StateSpace& sys, const json& provenance) {
  sys.validate();
  json j = json::object();
  put_labels(j, sys);
  j["A"] = common::matrix_to_json(sys.A);
  j["B"] = common::matrix_to_json(sys.B);
  j["C"] = common::matrix_to_json(sys.C);
  j["D"] = common::matrix_to_json(sys.D);
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
  j["Ad"] = common::matrix_to_json(d.sys.A);
  j["Bd"] = common::matrix_to_json(d.sys.B);
  j["Cd"] = common::matrix_to_json(d.sys.C);
  j["Dd"] = common::matrix_to_json(d.sys.D);
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
    throw common::InputError(r.place("method"), e.what());
  }
  d.dt = r.number("dt");
  if (d.dt <= 0) throw common::InputError(r.place("dt"), "must be > 0");
  d.prewarp_hz = r.number("prewarp_hz");
  if (d.prewarp_hz < 0) throw common::InputError(r.place("prewarp_hz"), "must be >= 0");
  d.spectral_radius = r.number("spectral_radius");
  d.sys = read_system(r, "Ad", "Bd", "Cd", "Dd");
  // The stated spectral radius is what users and the runtime trust; catch a hand-edited Ad.
  const double rho = spectral_radius(d.sys.A);
  if (std::abs(rho - d.spectral_radius) > 1e-9 * std::max(1.0, rho))
    throw common::InputError(r.place("spectral_radius"), "is " + json(d.spectral_radius).dump() +
                                                             " but Ad's is " + json(rho).dump() +
                                                             "; the file was edited or corrupted");
  out.provenance = read_provenance(r, j);
  return out;
}

ContinuousArtefact read_continuous(const std::filesystem::path& file) {
  return continuous_from_json(common::parse_json_file(file), file.string());
}

DiscreteArtefact read_discrete(const std::filesystem::path& file) {
  return discrete_from_json(common::parse_json_file(file), file.string());
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
  // Known keys in a fixed order, then the rest.
  common::write_json_atomically(
      file, j,
      {"method", "dt", "prewarp_hz", "spectral_radius", "states", "inputs", "outputs", "A", "B",
       "C", "D", "Ad", "Bd", "Cd", "Dd", "provenance"});
}

}  // namespace flexloop::plant::lti
