// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/schema_conversion.hpp"

#include <stdexcept>

namespace flexloop::scene {

plant::lti::VibrationCriterion vibration_criterion(artefact::FloorSpectrum spectrum) {
  using From = artefact::FloorSpectrum;
  using To = plant::lti::VibrationCriterion;
  switch (spectrum) {
    case From::kVcA:
      return To::kVcA;
    case From::kVcB:
      return To::kVcB;
    case From::kVcC:
      return To::kVcC;
    case From::kVcD:
      return To::kVcD;
    case From::kVcE:
      return To::kVcE;
    case From::kWhite:
      break;
  }
  throw std::invalid_argument("a white floor follows no vibration criterion");
}

}  // namespace flexloop::scene
