#pragma once
// The one place the offline side maps its own enums to the loop artefact's schema
// (artefact/loop_schema.hpp) and back: artefact/ knows nothing of plant/lti, whose enums name the
// same methods and curves.
#include "artefact/loop_schema.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/vibration_criterion.hpp"

namespace flexloop::scene {

/// The artefact's name for the method the plant was sampled with.
artefact::DiscretisationMethod artefact_method(plant::lti::DiscretisationMethod method);

/// The VC curve a floor spectrum follows. @throws std::invalid_argument for the white floor,
/// which follows none.
plant::lti::VibrationCriterion vibration_criterion(artefact::FloorSpectrum spectrum);

}  // namespace flexloop::scene
