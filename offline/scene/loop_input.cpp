// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/loop_input.hpp"
#include "common/build_info.hpp"
#include "common/input_error.hpp"
#include "common/sha256.hpp"

#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/scene_plant.hpp"

namespace flexloop::scene {

artefact::Provenance loop_provenance(const std::string& scene_path, const std::string& model_path) {
  return {scene_path,
          common::file_sha256(scene_path),
          model_path,
          common::file_sha256(model_path),
          common::build_info::kVersion,
          common::build_info::kGitHash};
}

artefact::LoopArtefact load_loop(const std::string& path, const LoopInputOptions& o) {
  if (artefact::is_loop_artefact_file(path)) return artefact::read_loop_artefact(path, o);
  Scene sc = load_scene(path);
  if (o.rate_hz > 0) sc.discretisation.rate_hz = o.rate_hz;
  const auto p = build_scene_plant(sc);
  require_stable_loop(p);
  artefact::LoopArtefact a =
      build_loop_artefact(p, sample_scene(p), o.form.value_or(artefact::PlantForm::kDense),
                          loop_provenance(path, sc.model_path));
  if (o.duration_s > 0) a.duration_s = o.duration_s;
  return a;
}

}  // namespace flexloop::scene
