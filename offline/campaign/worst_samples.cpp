#include "offline/campaign/worst_samples.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "common/atomic_file.hpp"

namespace flexloop::campaign {

namespace {

double json_number_or(const nlohmann::json& j, const char* key, double fallback) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

// max over the performance channels of rms / nominal rms (-inf when there is none).
double worst_rms_ratio(const nlohmann::json& sample, const nlohmann::json& nominal) {
  double worst = -std::numeric_limits<double>::infinity();
  if (!sample.contains("rms") || !sample["rms"].is_object() || !nominal.contains("rms"))
    return worst;
  for (const auto& [channel, value] : sample["rms"].items()) {
    const double n = json_number_or(nominal["rms"], channel.c_str(), 0.0);
    if (value.is_number() && n > 0) worst = std::max(worst, value.get<double>() / n);
  }
  return worst;
}

// A relative path of the nominal scene (a controller file) made absolute: the scene written
// elsewhere still finds it.
void make_absolute(toml::table& scene, const char* table, const char* key,
                   const std::filesystem::path& base) {
  auto* t = scene.get(table) ? scene.get(table)->as_table() : nullptr;
  const auto* n = t ? t->get(key) : nullptr;
  const auto v = n ? n->value<std::string>() : std::nullopt;
  if (v && !std::filesystem::path(*v).is_absolute())
    t->insert_or_assign(key, (base / *v).lexically_normal().string());
}

}  // namespace

std::vector<std::size_t> worst_samples(const std::vector<nlohmann::json>& samples,
                                       const nlohmann::json& nominal, std::size_t k) {
  std::vector<std::size_t> machines;
  bool any_unstable = false;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string status = samples[i].value("status", std::string());
    if (status != "stable" && status != "unstable") continue;
    machines.push_back(i);
    any_unstable = any_unstable || status == "unstable";
  }
  const double none = -std::numeric_limits<double>::infinity();
  auto key = [&](std::size_t i) {
    const auto& s = samples[i];
    return any_unstable ? std::pair{s.value("status", std::string()) == "unstable" ? 1.0 : 0.0,
                                    json_number_or(s, "spectral_radius", none)}
                        : std::pair{0.0, worst_rms_ratio(s, nominal)};
  };
  std::stable_sort(machines.begin(), machines.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) > key(b); });
  if (machines.size() > k) machines.resize(k);
  return machines;
}

SampleScene machine_scene(const MachineDocuments& docs, const nlohmann::json& plan,
                          const ParameterValues& values, const std::string& what,
                          const std::string& name_suffix, const std::string& model_file_name) {
  std::string header = "# flexloop campaign: " + what + "\n# scene " +
                       plan.at("scene").get<std::string>() + "\n# drawn:";
  for (const auto& [path, value] : values)
    header += " " + path + " = " + nlohmann::json(value).dump();
  header += "\n";
  // A scene holds the PI's design targets, not its gains: whoever runs this scene designs the PI
  // on this machine, where a frozen campaign ran the nominal machine's gains.
  if (plan.value("controller", std::string()) == "frozen" &&
      docs.nominal_machine().scene.controller.type == "pi_force_feedback")
    header +=
        "# the campaign froze the PI (the nominal machine's gains); run as it is, the PI is "
        "designed on this machine from [controller]\n";

  toml::table scene = docs.document(false, values);
  const auto base = std::filesystem::path(docs.scene_file()).parent_path();
  make_absolute(scene, "controller", "file", base);
  auto& scene_table = *scene.get("scene")->as_table();
  const auto name = scene_table.get("name")->value<std::string>().value_or("scene");
  scene_table.insert_or_assign("name", name + name_suffix);
  scene_table.insert_or_assign("model", model_file_name);
  return {header + toml_text(scene), header + toml_text(docs.document(true, values))};
}

SampleScene sample_scene(const MachineDocuments& docs, const nlohmann::json& plan,
                         const nlohmann::json& sample, const std::string& model_file_name) {
  ParameterValues values;
  for (const auto& [path, value] : sample.at("parameters").items())
    values.emplace_back(path, value.get<double>());
  const long index = sample.at("index").get<long>();
  const std::string what = "sample " + std::to_string(index) + " of plan " +
                           plan.at("plan_id").get<std::string>() + ", status " +
                           sample.value("status", std::string("?"));
  return machine_scene(docs, plan, values, what, "_sample_" + std::to_string(index),
                       model_file_name);
}

std::vector<std::string> write_worst_samples(const MachineDocuments& docs,
                                             const nlohmann::json& plan,
                                             const std::vector<nlohmann::json>& samples,
                                             std::size_t k, const std::string& out_dir) {
  const std::filesystem::path dir = std::filesystem::path(out_dir) / "worst";
  std::filesystem::create_directories(dir);
  std::vector<std::string> written;
  for (std::size_t i : worst_samples(samples, plan.at("nominal"), k)) {
    const std::string stem = "sample-" + std::to_string(samples[i].at("index").get<long>());
    const SampleScene s = sample_scene(docs, plan, samples[i], stem + "_model.toml");
    common::write_text_atomically(dir / (stem + "_model.toml"), s.model_text);
    common::write_text_atomically(dir / (stem + ".toml"), s.scene_text);
    written.push_back((dir / (stem + ".toml")).string());
  }
  return written;
}

}  // namespace flexloop::campaign
