// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The one place the offline side maps its own enums to the loop artefact's schema
// (artefact/loop_schema.hpp): artefact/ knows nothing of plant/lti, whose VC curves name the same
// spectra. (The discretisation method is one enum for both: numeric/discretisation_method.hpp.)
#include "artefact/loop_schema.hpp"
#include "plant/lti/vibration_criterion.hpp"

namespace flexloop::scene {

/// The VC curve a floor spectrum follows. @throws std::invalid_argument for the white floor,
/// which follows none.
plant::lti::VibrationCriterion vibration_criterion(artefact::FloorSpectrum spectrum);

}  // namespace flexloop::scene
