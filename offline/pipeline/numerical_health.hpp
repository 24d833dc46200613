// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The numerical health of a scene (issue 17; doc/testing.md "Hard cases"): the figures that say
// whether the offline numbers can be trusted and whether the online plant can run them, each
// with a verdict. `flexloop analyse SCENE` prints them and writes them to analysis.json; the loop
// commands are guarded by the checks that refuse (scene::require_stable_loop, discretise's
// stability guard, the float plants' start-up, to_modal_form).
//
// - static stability: divergent modes, and how far a preload is from buckling (its multiplier).
// - exponential: the 1-norm of the matrix ZOH/FOH exponentiate ([A B; 0 0] T, plant/lti/
//   discretise.hpp hold_matrix) before and after its power-of-two balancing
//   (plant/lti/balanced_exponential.hpp); tested up to 1e8.
// - modes above Nyquist: natural frequencies above rate/2 (ZOH/FOH sample them exactly, aliased
//   as the hardware would see them; Tustin warps them into the band).
// - mass matrix: condition number of the dynamic coordinates' mass matrix M̄dd over its massive
//   directions, and the massless directions that are condensed.
// - sampled loop: the spectral radius of the loop as it runs and its verdict (the one the loop
//   commands use), when the scene has a controller.
// - float: for each decaying pole of the modal plant, its distance to the unit circle against
//   what rounding Λ - I to float moves it by (plant/runtime/pole_precision.hpp); the smallest
//   ratio is the headroom; and how much float changes each pole's decay. The float plants refuse
//   a pole float puts on or outside the circle, or whose decay it changes by more than 10 %.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "offline/scene/scene_plant.hpp"

namespace flexloop::pipeline {

struct HealthCheck {
  std::string name;     ///< e.g. "exponential"
  std::string figures;  ///< what was measured, with numbers
  std::string verdict;  ///< what flexloop does about it / whether it is fine
  bool ok = true;       ///< false: the user should act (the verdict says how)
};

using controller::design::SampledLoopStability;

/// `loop`: the sampled loop's stability when it was formed (scenes with a controller).
std::vector<HealthCheck> numerical_health(const scene::ScenePlant& p,
                                          const plant::lti::DiscreteStateSpace& sampled_plant,
                                          const std::optional<SampledLoopStability>& loop);

/// Printed as "numerical health:" and one line per check.
void print_health(const std::vector<HealthCheck>& checks);
nlohmann::json health_json(const std::vector<HealthCheck>& checks);

}  // namespace flexloop::pipeline
