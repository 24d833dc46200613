// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The numbers of a machine a campaign may vary, addressed by path (doc/campaign.md "Paths"):
//   model  element.<id>.<key>   stiffness, damping, mass, E, G, A, I, Iy, Iz, J, rho
//                               (an array such as a beam's damping: element.<id>.damping[k])
//          node.<id>.mass       node.<id>.inertia (2-D: a number); node.<id>.inertia[k] (3-D:
//                               entry k, 0-based, of the array as written: Ixx Iyy Izz [Ixy Ixz
//                               Iyz])
//   scene  effects.actuator.gain|force_limit_n|lag_s,
//          effects.force_sensor|accelerometer.gain_error|noise_rms_*|adc_range_*,
//          floor.rms_mps2, controller.omega_d_hz|zeta|leak_hz (the PI design)
// A path names a number written in the file (a default that is not written is not a parameter:
// write it to vary it). A '*' in a segment matches any run of characters (element.*.stiffness:
// the elements that have the key). A machine with drawn values is made on the TOML documents:
// the value is set at its path and the document goes through the project's own strict readers
// (the second halves of plant::model::parse_model and scene::parse_scene: model_from_toml and
// scene_from_toml, on the document as toml++ holds it, not written and parsed again), so every
// sample passes the checks a user's file passes.
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "offline/scene/scene.hpp"
#include "plant/model/model.hpp"

namespace flexloop::campaign {

/// Values by concrete path.
using ParameterValues = std::vector<std::pair<std::string, double>>;

/// What a number may physically be: above `lower` (or at it when `lower_inclusive`); no bound
/// when lower is -infinity. The reason names it ("a stiffness must not be negative").
struct PhysicalBound {
  double lower;
  bool lower_inclusive;
  std::string reason;
};

/// Where a concrete path's number stands in its document, its nominal value and its bound.
struct ParameterSite {
  std::string path;
  bool model = true;                     ///< the model file (else the scene file)
  std::vector<std::string> tables;       ///< from the root; for an array of tables, its name
  std::size_t item = std::string::npos;  ///< the index in that array of tables
  std::string key;
  int entry = -1;  ///< the index in an array value (node.1.inertia[2]); -1: a number
  double nominal = 0;
  PhysicalBound bound;
};

/// A machine: its scene and its model, both read by the project's readers.
struct Machine {
  scene::Scene scene;
  plant::model::Model model;
};

class MachineDocuments {
 public:
  /// Reads the scene file and its model file (scene.model_path).
  explicit MachineDocuments(const std::string& scene_path);
  MachineDocuments(std::string scene_text, std::string scene_file, std::string model_text,
                   std::string model_file);

  /// Every concrete path, model first, in document order.
  const std::vector<std::string>& paths() const { return paths_; }
  /// @throws std::out_of_range for an unknown path.
  const ParameterSite& site(const std::string& path) const;
  /// The concrete paths a pattern matches (in document order); empty when none.
  std::vector<std::string> expand(const std::string& pattern) const;

  const Machine& nominal_machine() const { return nominal_; }
  /// The machine with `values` set (unknown paths: std::out_of_range). A value the readers
  /// refuse throws their flexloop::InputError.
  Machine apply(const ParameterValues& values) const;
  /// The model's (model = true) or the scene's TOML document with `values` set.
  toml::table document(bool model, const ParameterValues& values) const;
  /// The documents with `values` set, as TOML text (toml++'s serialisation, no comments).
  std::string model_text(const ParameterValues& values) const;
  std::string scene_text(const ParameterValues& values) const;
  const std::string& scene_file() const { return scene_file_; }
  const std::string& model_file() const { return model_file_; }

 private:
  void collect_model_sites();
  void collect_scene_sites();

  std::string scene_file_, model_file_;
  toml::table scene_doc_, model_doc_;
  std::vector<ParameterSite> sites_;
  std::vector<std::string> paths_;
  Machine nominal_;
};

/// True when `path` addresses the model (element.*, node.*), false for the scene.
bool is_model_path(const std::string& path);
/// A TOML document as text (toml++'s serialisation).
std::string toml_text(const toml::table& document);
/// A '*'-glob over the segments of a path (split at '.'), segment by segment.
bool path_matches(const std::string& pattern, const std::string& path);
/// Levenshtein distance (insertions, deletions, substitutions).
std::size_t edit_distance(const std::string& a, const std::string& b);
/// The `count` names nearest to `wrong` (edit distance, then alphabetical).
std::vector<std::string> nearest_names(const std::string& wrong,
                                       const std::vector<std::string>& names,
                                       std::size_t count = 3);

}  // namespace flexloop::campaign
