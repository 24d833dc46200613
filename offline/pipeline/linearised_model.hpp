// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The step `linearise` and `analyse` share: read a model file, linearise it about its
// stationary configuration, build the state space for the chosen channels, and find the
// natural frequencies (massless coordinates condensed statically when the mass matrix of the
// dynamic coordinates is singular, in the state space and for the frequencies alike).
#include <string>
#include <vector>

#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model.hpp"

namespace flexloop::pipeline {

struct LinearisedModel {
  plant::model::Model model;
  plant::model::Linearisation lin;
  plant::lti::StateSpace ss;
  Eigen::VectorXd natural_frequencies_hz;
  Eigen::MatrixXd mode_shapes;  // columns over the dynamic coordinates, mass-normalised
  int massless_condensed = 0;   // dynamic directions without mass, condensed for the frequencies
  plant::lti::Condensation condensation;  // what the state space condensed (the same directions)
  plant::lti::StaticStability statics;    // of those modes, with the buckling multipliers
};

/// Channels: defaults when empty (every prescribed coordinate as acc:, every actuated
/// deformation as stress: in; every dynamic coordinate's pos: out).
LinearisedModel linearise_model_file(const std::string& path, std::vector<std::string> inputs,
                                     std::vector<std::string> outputs);

}  // namespace flexloop::pipeline
