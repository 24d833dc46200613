// SPDX-License-Identifier: BSD-3-Clause
#include "controller/fmu/fmu_description.hpp"

#include <algorithm>
#include <cctype>
#include <pugixml.hpp>
#include <set>

#include "common/input_error.hpp"

namespace flexloop::controller::fmu {

namespace {

// "a real input", "an Integer output": what a variable is, for messages.
std::string what_it_is(const FmuVariable& v) {
  const std::string type = v.real() ? "real" : v.type.empty() ? "untyped" : v.type;
  const bool vowel = std::string("aeiouAEIOU").find(type[0]) != std::string::npos;
  return (vowel ? "an " : "a ") + type + " " + v.causality;
}

// The valueReference attribute: required (FMI 2.0, 2.2.7), an unsigned 32-bit integer.
unsigned value_reference(const pugi::xml_node& v, const std::string& name, const std::string& fmu) {
  const pugi::xml_attribute a = v.attribute("valueReference");
  if (!a)
    throw common::InputError(fmu, "modelDescription.xml: variable '" + name +
                                      "' has no valueReference (the standard requires one)");
  const std::string text = a.value();
  const bool digits =
      !text.empty() && text.size() <= 10 &&
      std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
  if (!digits || std::stoull(text) > 0xffffffffULL)
    throw common::InputError(fmu, "modelDescription.xml: variable '" + name +
                                      "' has valueReference \"" + text +
                                      "\", not an unsigned 32-bit integer");
  return static_cast<unsigned>(std::stoull(text));
}

// The <ModelVariables>, each with a unique name, a value reference and its type element.
std::vector<FmuVariable> read_variables(const pugi::xml_node& root, const std::string& fmu) {
  std::vector<FmuVariable> variables;
  std::set<std::string> names;
  int index = 0;
  for (const pugi::xml_node v : root.child("ModelVariables").children("ScalarVariable")) {
    ++index;
    FmuVariable x;
    x.name = v.attribute("name").value();
    if (x.name.empty())
      throw common::InputError(
          fmu, "modelDescription.xml: ScalarVariable " + std::to_string(index) + " has no name");
    if (!names.insert(x.name).second)
      throw common::InputError(fmu, "modelDescription.xml: variable '" + x.name +
                                        "' appears twice (names must be unique)");
    x.value_reference = value_reference(v, x.name, fmu);
    x.causality = v.attribute("causality").as_string("local");
    x.variability = v.attribute("variability").as_string("continuous");
    for (const char* type : {"Real", "Integer", "Boolean", "String", "Enumeration"})
      if (v.child(type)) x.type = type;
    if (x.type.empty())
      throw common::InputError(fmu, "modelDescription.xml: variable '" + x.name +
                                        "' has no type (Real, Integer, Boolean, String or "
                                        "Enumeration)");
    variables.push_back(std::move(x));
  }
  return variables;
}

// The <CoSimulation> capabilities the loader needs or honours.
void read_co_simulation(const pugi::xml_node& cs, const std::string& fmu, FmuDescription& d) {
  d.model_identifier = cs.attribute("modelIdentifier").value();
  if (d.model_identifier.empty())
    throw common::InputError(fmu, "modelDescription.xml: <CoSimulation> has no modelIdentifier");
  if (!is_c_identifier(d.model_identifier))
    throw common::InputError(fmu, "modelDescription.xml: modelIdentifier \"" + d.model_identifier +
                                      "\" is not a C identifier ([A-Za-z_][A-Za-z0-9_]*): it "
                                      "names the library binaries/linux64/<modelIdentifier>.so");
  if (cs.attribute("needsExecutionTool").as_bool(false))
    throw common::InputError(
        fmu,
        "needsExecutionTool=\"true\": the FMU runs only inside the tool that exported it, which "
        "flexloop does not start; export a standalone (tool-independent) Co-Simulation FMU");
  d.variable_step = cs.attribute("canHandleVariableCommunicationStepSize").as_bool(false);
  d.only_once_per_process = cs.attribute("canBeInstantiatedOnlyOncePerProcess").as_bool(false);
  d.can_run_asynchronously = cs.attribute("canRunAsynchronuously").as_bool(false);
}

}  // namespace

bool is_c_identifier(std::string_view s) {
  const auto letter = [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
  };
  return !s.empty() && letter(s[0]) && std::all_of(s.begin(), s.end(), [&](char c) {
    return letter(c) || (c >= '0' && c <= '9');
  });
}

const FmuVariable& FmuDescription::real(const std::string& name, const std::string& causality,
                                        const std::string& fmu) const {
  std::string same_causality;
  for (const auto& v : variables) {
    if (v.name == name) {
      if (!v.real() || v.causality != causality)
        throw common::InputError(
            fmu, "variable '" + name + "' is " + what_it_is(v) + ", not a real " + causality);
      if (causality == "parameter" && v.variability != "fixed" && v.variability != "tunable")
        throw common::InputError(
            fmu, "variable '" + name + "' is a real parameter of variability \"" + v.variability +
                     "\": flexloop sets parameters of variability \"fixed\" "
                     "or \"tunable\" only");
      return v;
    }
    if (v.real() && v.causality == causality)
      same_causality += (same_causality.empty() ? "" : ", ") + v.name;
  }
  throw common::InputError(fmu, "no variable '" + name + "' (its real " + causality + "s: " +
                                    (same_causality.empty() ? "none" : same_causality) + ")");
}

FmuDescription read_fmu_description(const std::filesystem::path& dir, const std::string& fmu) {
  const auto file = dir / "modelDescription.xml";
  if (!std::filesystem::is_regular_file(file))
    throw common::InputError(fmu, "not an FMU: the archive has no modelDescription.xml");
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_file(file.c_str());
  if (!parsed)
    throw common::InputError(fmu, std::string("modelDescription.xml: ") + parsed.description() +
                                      " at byte " + std::to_string(parsed.offset));
  const pugi::xml_node root = doc.child("fmiModelDescription");
  if (!root) throw common::InputError(fmu, "modelDescription.xml has no <fmiModelDescription>");
  const std::string version = root.attribute("fmiVersion").value();
  if (version != "2.0")
    throw common::InputError(
        fmu, "fmiVersion is \"" + version + "\": flexloop runs FMI 2.0 Co-Simulation FMUs only");
  const pugi::xml_node cs = root.child("CoSimulation");
  if (!cs)
    throw common::InputError(fmu,
                             root.child("ModelExchange")
                                 ? "a Model Exchange FMU only: flexloop runs Co-Simulation FMUs"
                                 : "modelDescription.xml has no <CoSimulation>");
  FmuDescription d;
  read_co_simulation(cs, fmu, d);
  d.guid = root.attribute("guid").value();
  if (d.guid.empty()) throw common::InputError(fmu, "modelDescription.xml: no guid");
  if (const auto step = root.child("DefaultExperiment").attribute("stepSize"))
    d.step_size = step.as_double();
  d.variables = read_variables(root, fmu);
  return d;
}

}  // namespace flexloop::controller::fmu
