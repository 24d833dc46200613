// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Part of the loop artefact's schema: the fields that take one of a few names in the file (the
// plant's form, the discretisation method, the floor's spectrum). Each name is parsed once, where
// the artefact (or the scene, or a command line) is read; past that, code compares the enums,
// never the strings. The names are the file's (doc/loop_artefact.md) and must not change.
// Header only and free of JSON: the plant runtime dispatches on PlantForm.
#include <cstddef>
#include <stdexcept>
#include <string>

#include "numeric/discretisation_method.hpp"

namespace flexloop::artefact {

/// The form the online side steps the plant in.
enum class PlantForm { kDense, kModal };

/// How the continuous plant was sampled: the enum the offline discretisation computes with
/// (numeric/discretisation_method.hpp; plant/lti/discretise.hpp), with the schema's names below.
using numeric::DiscretisationMethod;

/// The floor's excitation: white (band-limited by the sample rate) or a vibration-criterion curve.
enum class FloorSpectrum { kWhite, kVcA, kVcB, kVcC, kVcD, kVcE };

template <class E>
struct SchemaName {
  E value;
  const char* name;
};

inline constexpr SchemaName<PlantForm> kPlantFormNames[] = {{PlantForm::kDense, "dense"},
                                                            {PlantForm::kModal, "modal"}};
inline constexpr SchemaName<DiscretisationMethod> kDiscretisationMethodNames[] = {
    {DiscretisationMethod::kZeroOrderHold, "zoh"},
    {DiscretisationMethod::kFirstOrderHold, "foh"},
    {DiscretisationMethod::kTustin, "tustin"},
    {DiscretisationMethod::kForwardEuler, "euler"},
    {DiscretisationMethod::kBackwardEuler, "backward-euler"}};
inline constexpr SchemaName<FloorSpectrum> kFloorSpectrumNames[] = {
    {FloorSpectrum::kWhite, "white"}, {FloorSpectrum::kVcA, "VC-A"}, {FloorSpectrum::kVcB, "VC-B"},
    {FloorSpectrum::kVcC, "VC-C"},    {FloorSpectrum::kVcD, "VC-D"}, {FloorSpectrum::kVcE, "VC-E"}};

/// The value's name in a table above (every enumerator has one).
template <class E, std::size_t N>
std::string schema_name(const SchemaName<E> (&names)[N], E value) {
  for (const auto& n : names)
    if (n.value == value) return n.name;
  return "?";
}

/// The value a name stands for. @throws std::invalid_argument
/// 'is "x"; expected "a", "b" or "c"' (a reader puts its file and key in front).
template <class E, std::size_t N>
E parse_schema_name(const SchemaName<E> (&names)[N], const std::string& name) {
  std::string expected;
  for (std::size_t k = 0; k < N; ++k) {
    if (names[k].name == name) return names[k].value;
    expected += (k == 0       ? "\""
                 : k + 1 == N ? " or \""
                              : ", \"") +
                std::string(names[k].name) + "\"";
  }
  throw std::invalid_argument("is \"" + name + "\"; expected " + expected);
}

inline std::string to_string(PlantForm f) {
  return schema_name(kPlantFormNames, f);
}
inline std::string to_string(DiscretisationMethod m) {
  return schema_name(kDiscretisationMethodNames, m);
}
inline std::string to_string(FloorSpectrum s) {
  return schema_name(kFloorSpectrumNames, s);
}

inline PlantForm parse_plant_form(const std::string& name) {
  return parse_schema_name(kPlantFormNames, name);
}
inline DiscretisationMethod parse_discretisation_method(const std::string& name) {
  return parse_schema_name(kDiscretisationMethodNames, name);
}
inline FloorSpectrum parse_floor_spectrum(const std::string& name) {
  return parse_schema_name(kFloorSpectrumNames, name);
}

}  // namespace flexloop::artefact
