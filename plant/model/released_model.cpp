// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/released_model.hpp"

#include "common/input_error.hpp"
#include "plant/model/model_parser.hpp"

namespace flexloop::plant::model {

Model release_to_prescribed(const Model& m, const std::string& label) {
  Model r = m;
  if (const int i = m.coordinate_index(label); i >= 0) {
    if (m.coordinate_roles[i] != CoordinateRole::kFixed)
      throw common::InputError("output 'reaction:" + label + "'",
                               "'" + label + "' is not a fixed coordinate");
    if (label[0] == 'l')  // an Euler parameter: its generalised force is not a physical moment
      throw common::InputError(
          "output 'reaction:" + label + "'",
          "reactions are available on translations (and planar angles), not on Euler parameters");
    r.coordinate_roles[i] = CoordinateRole::kPrescribed;
  } else if (const int k = m.deformation_index(label); k >= 0) {
    if (m.deformation_roles[k] == DeformationRole::kInert)
      throw common::InputError(
          "output 'stress:" + label + "'",
          "'" + label +
              "' joins fixed coordinates only: its stress is not determined by the model");
    if (m.deformation_roles[k] != DeformationRole::kRigid)
      throw common::InputError("output 'stress:" + label + "'",
                               "'" + label + "' is not a rigid deformation");
    r.deformation_roles[k] = DeformationRole::kPrescribed;
  } else {
    throw common::InputError("output '" + label + "'",
                             "unknown coordinate or deformation '" + label + "'");
  }
  r.generalised.push_back(label);
  mark_inert_deformations(r);
  return r;
}

}  // namespace flexloop::plant::model
