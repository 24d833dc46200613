#include "controller/fmu/fmu_description.hpp"

#include <pugixml.hpp>

#include "common/input_error.hpp"

namespace flexloop::controller::fmu {

const FmuVariable& FmuDescription::real(const std::string& name, const std::string& causality,
                                        const std::string& fmu) const {
  std::string same_causality;
  for (const auto& v : variables) {
    if (v.name == name) {
      if (v.real && v.causality == causality) return v;
      throw common::InputError(fmu, "variable '" + name + "' is " +
                                        (v.real ? "a real " : "a non-real ") + v.causality +
                                        ", not a real " + causality);
    }
    if (v.real && v.causality == causality)
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
  d.model_identifier = cs.attribute("modelIdentifier").value();
  d.guid = root.attribute("guid").value();
  if (d.model_identifier.empty() || d.guid.empty())
    throw common::InputError(fmu, "modelDescription.xml: no modelIdentifier or guid");
  d.variable_step = cs.attribute("canHandleVariableCommunicationStepSize").as_bool(false);
  if (const auto step = root.child("DefaultExperiment").attribute("stepSize"))
    d.step_size = step.as_double();
  for (const pugi::xml_node v : root.child("ModelVariables").children("ScalarVariable"))
    d.variables.push_back({v.attribute("name").value(), v.attribute("causality").as_string("local"),
                           v.attribute("valueReference").as_uint(), bool(v.child("Real"))});
  return d;
}

}  // namespace flexloop::controller::fmu
