// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/plan_file.hpp"

#include <dlfcn.h>

#include <string>
#include <string_view>

#include "artefact/loop_artefact.hpp"
#include "common/build_info.hpp"
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

std::string nominal_artefact_sha256(const std::string& scene_path) {
  return common::text_sha256(artefact::to_json(scene::load_loop(scene_path)).dump());
}

namespace {

void require_unchanged(const std::string& plan_path, const std::string& what,
                       const std::string& planned, const std::string& now) {
  if (planned != now)
    throw common::InputError(plan_path, what + " changed since the plan was made (SHA-256 " +
                                            planned.substr(0, 16) + " in the plan, " +
                                            now.substr(0, 16) +
                                            " now): its samples would not be the plan's; make "
                                            "a new plan");
}

}  // namespace

void require_plan_inputs_unchanged(const nlohmann::json& plan, const std::string& plan_path) {
  struct Input {
    const char *key, *hash, *name;
  };
  for (const Input& in :
       {Input{"scene", "scene_sha256", "scene"}, Input{"model", "model_sha256", "model"},
        Input{"uncertain", "uncertain_sha256", "uncertain"},
        Input{"controller_file", "controller_file_sha256", "controller"}}) {
    if (!plan.contains(in.key)) continue;  // a scene without a controller file
    const std::string path = plan.at(in.key).get<std::string>();
    require_unchanged(plan_path, std::string("the ") + in.name + " file " + path,
                      plan.at(in.hash).get<std::string>(), common::file_sha256(path));
  }
  if (plan.contains("nominal_artefact_sha256"))
    require_unchanged(plan_path,
                      "the nominal loop artefact (what this flexloop builds from the scene; "
                      "another flexloop build makes another)",
                      plan.at("nominal_artefact_sha256").get<std::string>(),
                      nominal_artefact_sha256(plan.at("scene").get<std::string>()));
}

namespace {

// The file of the flexloop code that computes a line: the program, or the shared object this
// code is linked into (the Python module, whose process is python3's).
std::string computing_binary() {
  static const char anchor = 0;
  Dl_info info{};
  if (::dladdr(&anchor, &info) != 0 && info.dli_fname != nullptr &&
      std::string_view(info.dli_fname).ends_with(".so"))
    return info.dli_fname;
  return "/proc/self/exe";
}

}  // namespace

nlohmann::json line_build() {
  static const std::string build = common::file_sha256(computing_binary()).substr(0, 16);
  return {{"version", common::build_info::kVersion}, {"build", build}};
}

}  // namespace flexloop::campaign
