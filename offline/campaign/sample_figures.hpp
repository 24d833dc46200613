#pragma once
// TEMPORARY (campaign-core's branch): the declarations of CAMPAIGN.md, so that this branch
// compiles before campaign-figures' sample_figures.* is merged. The lead takes theirs.
#include <nlohmann/json.hpp>
#include <vector>

#include "offline/scene/scene.hpp"
#include "plant/model/model.hpp"

namespace flexloop::campaign {

enum class ControllerMode { kFrozen, kRedesigned };
struct SampleSettings {
  ControllerMode mode = ControllerMode::kFrozen;
  std::vector<double> sigma_grid_hz;
};
class SampleEvaluator {
 public:
  SampleEvaluator(const scene::Scene& nominal_scene, const plant::model::Model& nominal_model,
                  SampleSettings settings);
  nlohmann::json evaluate(const scene::Scene& scene, const plant::model::Model& model) const;
  const nlohmann::json& nominal() const;

 private:
  nlohmann::json nominal_;
};

}  // namespace flexloop::campaign
