// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Offline: a scene's loop artefact (artefact/loop_artefact.hpp) from its offline pipeline
// (scene_plant.hpp): the plant sampled at the scene's rate and method (and in modal form when
// asked), the channel map with units, the controller (the PI parameters, or the user's discrete
// state space) at the loop's rate with what the hardware effects imply (the actuator limit for
// the anti-windup, the sensor + transport delay of the controller's own force), the floor's
// discrete shaping filter, the effects and the run.
#include <string>

#include "artefact/loop_artefact.hpp"
#include "offline/scene/scene_plant.hpp"

namespace flexloop::scene {

/// The SI unit of a channel of the model ("acc:x.3" -> "m/s^2", "stress:e1.4" -> "N", a rotation
/// -> "rad", "N m", ...).
std::string channel_unit(const std::string& channel);

/// The PI parameters of a scene at sample time dt with what its hardware effects imply.
artefact::PiParameters pi_parameters_with_hardware(const ScenePlant& p, double dt);

/// A controller FMU scene's FMU (absolute path and SHA-256), parameters and the FMU variable of
/// each sensor and actuator. @throws flexloop::InputError when the file cannot be read.
artefact::FmuParameters fmu_parameters(const Scene& sc);

/// A state-space scene's controller (p.state_space) with what its hardware effects imply, and
/// the sampled plant's own actuator -> sensor feedthrough D22, which the runtime removes.
artefact::StateSpaceParameters state_space_parameters_with_hardware(const ScenePlant& p,
                                                                    const SampledScene& sampled);

/// The artefact without its stationary starts (a.start left empty: what the loop's figures need,
/// offline/pipeline/loop_figures.hpp, without the cost of the two covariances).
/// @throws flexloop::InputError naming the scene when the modal form is refused.
artefact::LoopArtefact loop_artefact_without_start(const ScenePlant& p, const SampledScene& sampled,
                                                   artefact::PlantForm form,
                                                   const artefact::Provenance& provenance = {});

/// The modal form is computed here (a defective plant is refused).
/// @throws flexloop::InputError naming the scene when the modal form is refused.
artefact::LoopArtefact build_loop_artefact(const ScenePlant& p, const SampledScene& sampled,
                                           artefact::PlantForm form,
                                           const artefact::Provenance& provenance = {});

}  // namespace flexloop::scene
