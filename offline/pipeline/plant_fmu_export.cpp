// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/plant_fmu_export.hpp"

#include <zip.h>

#include <unistd.h>
#include <cstdio>
#include <map>
#include <pugixml.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/build_info.hpp"
#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "offline/pipeline/si_unit.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/plant_fmu/plant_fmu_variables.hpp"

namespace flexloop::pipeline {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

void attribute(pugi::xml_node n, const char* name, const std::string& value) {
  n.append_attribute(name) = value.c_str();
}

// Adds the outputs (1-based indices in ModelVariables), each depending on no input
// (dependencies=""), which is exact: the outputs at a communication point are the sample there,
// which reads the command held over the step before it (the plant's D acts on the held force,
// plant/runtime/simulated_hardware.hpp), never the inputs set at that point; they change only in
// fmi2DoStep. The same holds in initialization mode, where they are the sample at t = 0.
void list_outputs(pugi::xml_node parent, const char* name,
                  const std::vector<plant_fmu::PlantFmuVariable>& v) {
  auto list = parent.append_child(name);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!v[i].input) {
      auto u = list.append_child("Unknown");
      attribute(u, "index", std::to_string(i + 1));
      attribute(u, "dependencies", "");
    }
}

// The SI unit of each variable, by the artefact's unit string. @throws flexloop::InputError naming
// the artefact and the channel whose unit does not read (si_unit.hpp's grammar).
std::map<std::string, SiUnit> variable_units(const artefact::LoopArtefact& a,
                                             const std::vector<plant_fmu::PlantFmuVariable>& v) {
  std::map<std::string, SiUnit> units;
  for (const auto& variable : v) {
    if (units.count(variable.unit)) continue;
    try {
      units.emplace(variable.unit, parse_si_unit(variable.unit));
    } catch (const std::invalid_argument& e) {
      throw common::InputError(a.source, "channel " + variable.name + ": " + e.what() +
                                             "; the plant FMU declares the unit of every variable");
    }
  }
  return units;
}

// <UnitDefinitions>: one <Unit> per Modelica name, its BaseUnit exponents (factor 1: SI).
void define_units(pugi::xml_node root, const std::map<std::string, SiUnit>& units) {
  auto list = root.append_child("UnitDefinitions");
  std::map<std::string, const SiUnit*> by_name;
  for (const auto& [text, unit] : units) by_name.emplace(unit.name, &unit);
  for (const auto& [name, unit] : by_name) {
    auto u = list.append_child("Unit");
    attribute(u, "name", name);
    auto base = u.append_child("BaseUnit");
    for (std::size_t b = 0; b < unit->exponents.size(); ++b)
      if (unit->exponents[b] != 0)
        attribute(base, SiUnit::kBase[b], std::to_string(unit->exponents[b]));
  }
}

void declare_log_categories(pugi::xml_node root) {
  auto list = root.append_child("LogCategories");
  for (const auto& c : plant_fmu::kLogCategories) {
    auto category = list.append_child("Category");
    attribute(category, "name", c.name);
    attribute(category, "description", c.description);
  }
}

}  // namespace

std::string plant_fmu_description(const artefact::LoopArtefact& a, const std::string& guid) {
  pugi::xml_document doc;
  auto decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  auto root = doc.append_child("fmiModelDescription");
  attribute(root, "fmiVersion", "2.0");
  attribute(root, "modelName", "flexloop plant: " + a.name);
  attribute(root, "guid", guid);
  attribute(root, "description",
            "The discrete plant of loop '" + a.name + "' (" + artefact::to_string(a.method) +
                " at " + number(a.rate_hz) +
                " Hz) with its simulated hardware and floor: the actuators' commands in, the "
                "sensors and performance sensors out, one step per loop period");
  attribute(root, "generationTool", std::string("flexloop ") + common::build_info::kVersion);
  attribute(root, "variableNamingConvention", "flat");
  attribute(root, "numberOfEventIndicators", "0");
  auto cs = root.append_child("CoSimulation");
  attribute(cs, "modelIdentifier", plant_fmu::kModelIdentifier);
  attribute(cs, "needsExecutionTool", "false");
  attribute(cs, "canHandleVariableCommunicationStepSize", "false");
  attribute(cs, "canInterpolateInputs", "false");
  attribute(cs, "canRunAsynchronuously", "false");
  attribute(cs, "canBeInstantiatedOnlyOncePerProcess", "false");
  attribute(cs, "canNotUseMemoryManagementFunctions", "true");
  attribute(cs, "canGetAndSetFMUstate", "false");
  attribute(cs, "canSerializeFMUstate", "false");
  attribute(cs, "providesDirectionalDerivative", "false");
  const auto variables = plant_fmu::plant_fmu_variables(a);
  const auto units = variable_units(a, variables);
  define_units(root, units);
  declare_log_categories(root);
  auto experiment = root.append_child("DefaultExperiment");
  attribute(experiment, "startTime", "0");
  attribute(experiment, "stopTime", number(a.duration_s));
  attribute(experiment, "stepSize", number(a.dt()));

  auto list = root.append_child("ModelVariables");
  for (const auto& v : variables) {
    auto sv = list.append_child("ScalarVariable");
    attribute(sv, "name", v.name);
    attribute(sv, "valueReference", std::to_string(v.value_reference));
    attribute(sv, "causality", v.input ? "input" : "output");
    attribute(sv, "variability", "discrete");
    if (!v.input) attribute(sv, "initial", "calculated");
    auto real = sv.append_child("Real");
    attribute(real, "unit", units.at(v.unit).name);
    if (v.input) attribute(real, "start", "0");
  }
  auto rest = list.append_child("ScalarVariable");
  attribute(rest, "name", "start_at_rest");
  attribute(rest, "valueReference", std::to_string(plant_fmu::kStartAtRestReference));
  attribute(rest, "causality", "parameter");
  attribute(rest, "variability", "fixed");
  attribute(rest, "initial", "exact");
  attribute(rest, "description",
            "false: the open loop's stationary start, drawn from the artefact's seeds (as flexloop "
            "sim's controller-off run); true: at rest, the floor stationary");
  attribute(rest.append_child("Boolean"), "start", "false");

  auto structure = root.append_child("ModelStructure");
  list_outputs(structure, "Outputs", variables);
  list_outputs(structure, "InitialUnknowns", variables);
  std::ostringstream text;
  doc.save(text, "  ");
  return text.str();
}

void export_plant_fmu(const artefact::LoopArtefact& a, const std::filesystem::path& library,
                      const std::filesystem::path& fmu) {
  if (!std::filesystem::is_regular_file(library))
    throw common::InputError(library.string(),
                             "the plant FMU library is not there (build the target "
                             "flexloop_plant)");
  const std::string loop = artefact::to_json(a).dump(1);
  const std::string guid = "{flexloop-plant-" + common::text_sha256(loop) + "}";
  const std::string description = plant_fmu_description(a, guid);

  // A temporary archive beside the target, renamed over it when complete.
  const std::filesystem::path temporary =
      fmu.string() + ".partial-" + std::to_string(static_cast<long>(getpid()));
  int code = 0;
  zip_t* z = zip_open(temporary.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
  if (!z) throw common::InputError(fmu.string(), "cannot create the archive");
  const auto fail = [&](const std::string& what) {
    zip_discard(z);
    std::filesystem::remove(temporary);
    throw common::InputError(fmu.string(), what);
  };
  const auto add_text = [&](const char* name, const std::string& text) {
    zip_source_t* src = zip_source_buffer(z, text.data(), text.size(), 0);
    if (!src || zip_file_add(z, name, src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
      zip_source_free(src);
      fail(std::string("cannot add ") + name + ": " + zip_strerror(z));
    }
  };
  const std::string guid_line = guid + "\n";
  add_text("modelDescription.xml", description);
  add_text("resources/loop.json", loop);
  add_text("resources/guid.txt", guid_line);
  const std::string binary = std::string("binaries/linux64/") + plant_fmu::kModelIdentifier + ".so";
  zip_source_t* so = zip_source_file(z, library.c_str(), 0, -1);
  if (!so || zip_file_add(z, binary.c_str(), so, ZIP_FL_OVERWRITE) < 0) {
    zip_source_free(so);
    fail("cannot add " + library.string() + ": " + zip_strerror(z));
  }
  if (zip_close(z) != 0) {
    const std::string why = zip_strerror(z);
    zip_discard(z);
    std::filesystem::remove(temporary);
    throw common::InputError(fmu.string(), "cannot write the archive: " + why);
  }
  std::error_code ec;
  std::filesystem::rename(temporary, fmu, ec);
  if (ec) {
    std::filesystem::remove(temporary);
    throw common::InputError(fmu.string(), "cannot write: " + ec.message());
  }
}

}  // namespace flexloop::pipeline
