#include "offline/campaign/plan_file.hpp"

#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "common/toml_reader.hpp"
#include "offline/scene/loop_input.hpp"

namespace flexloop::campaign {

std::string plan_id_of(const nlohmann::json& plan) {
  nlohmann::json content = plan;
  content.erase("plan_id");
  return common::text_sha256(content.dump());
}

nlohmann::json with_plan_id(nlohmann::json plan) {
  plan["plan_id"] = plan_id_of(plan);
  return plan;
}

nlohmann::json read_plan(const std::string& path) {
  const std::string text = common::read_input_file(path, "campaign plan");
  nlohmann::json plan;
  try {
    plan = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw common::InputError(path, std::string("not a JSON campaign plan: ") + e.what());
  }
  if (!plan.is_object() || plan.value("format", "") != kPlanFormat)
    throw common::InputError(path, std::string("not a campaign plan (\"format\" is not \"") +
                                       kPlanFormat + "\"): make one with `flexloop campaign plan`");
  if (plan.value("version", 0) != kPlanVersion)
    throw common::InputError(path, "campaign plan version " + plan["version"].dump() + " is not " +
                                       std::to_string(kPlanVersion));
  if (!plan.contains("plan_id") || plan["plan_id"] != plan_id_of(plan))
    throw common::InputError(path,
                             "the plan's content does not match its plan_id (the plan was "
                             "edited): make a new one with `flexloop campaign plan`");
  return plan;
}

void require_plan_inputs_unchanged(const nlohmann::json& plan, const std::string& plan_path) {
  for (const auto& [file, hash] :
       {std::pair{"scene", "scene_sha256"}, std::pair{"model", "model_sha256"},
        std::pair{"uncertain", "uncertain_sha256"}}) {
    const std::string path = plan.at(file).get<std::string>();
    if (common::file_sha256(path) != plan.at(hash).get<std::string>())
      throw common::InputError(plan_path, std::string("the ") + file + " file " + path +
                                              " changed since the plan was made: its samples "
                                              "would not be the plan's; make a new plan");
  }
}

}  // namespace flexloop::campaign
