// SPDX-License-Identifier: BSD-3-Clause
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

WorstSamples::WorstSamples(const nlohmann::json& nominal, std::size_t k)
    : nominal_(nominal), k_(k) {}

namespace {

// a is a worse machine than b: its key larger, or the same key and the lower position.
bool worse(const WorstSamples::Candidate& a, const WorstSamples::Candidate& b) {
  if (a.key_first != b.key_first) return a.key_first > b.key_first;
  if (a.key_second != b.key_second) return a.key_second > b.key_second;
  return a.position < b.position;
}

}  // namespace

// A heap ordered by `worse`: its top is the least bad candidate kept, the first to go.
void WorstSamples::keep(std::vector<Candidate>& heap, const Candidate& c) const {
  if (k_ == 0) return;
  if (heap.size() == k_) {
    if (!worse(c, heap.front())) return;
    std::pop_heap(heap.begin(), heap.end(), worse);
    heap.pop_back();
  }
  heap.push_back(c);
  std::push_heap(heap.begin(), heap.end(), worse);
}

void WorstSamples::add(long position, const nlohmann::json& sample) {
  const std::string status = sample.value("status", std::string());
  if (status != "stable" && status != "unstable") return;
  const bool unstable = status == "unstable";
  any_unstable_ = any_unstable_ || unstable;
  const double none = -std::numeric_limits<double>::infinity();
  keep(by_radius_,
       {unstable ? 1.0 : 0.0, json_number_or(sample, "spectral_radius", none), position});
  keep(by_rms_, {0.0, worst_rms_ratio(sample, nominal_), position});
}

std::vector<long> WorstSamples::worst() const {
  std::vector<Candidate> kept = any_unstable_ ? by_radius_ : by_rms_;
  std::sort(kept.begin(), kept.end(), worse);
  std::vector<long> out;
  for (const Candidate& c : kept) out.push_back(c.position);
  return out;
}

std::vector<std::size_t> worst_samples(const std::vector<nlohmann::json>& samples,
                                       const nlohmann::json& nominal, std::size_t k) {
  WorstSamples tally(nominal, k);
  for (std::size_t i = 0; i < samples.size(); ++i) tally.add(static_cast<long>(i), samples[i]);
  std::vector<std::size_t> out;
  for (long i : tally.worst()) out.push_back(static_cast<std::size_t>(i));
  return out;
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

std::vector<std::string> write_sample_scenes(const MachineDocuments& docs,
                                             const nlohmann::json& plan,
                                             const std::vector<nlohmann::json>& worst,
                                             const std::string& out_dir) {
  const std::filesystem::path dir = std::filesystem::path(out_dir) / "worst";
  std::filesystem::create_directories(dir);
  std::vector<std::string> written;
  for (const nlohmann::json& sample : worst) {
    const std::string stem = "sample-" + std::to_string(sample.at("index").get<long>());
    const SampleScene s = sample_scene(docs, plan, sample, stem + "_model.toml");
    common::write_text_atomically(dir / (stem + "_model.toml"), s.model_text);
    common::write_text_atomically(dir / (stem + ".toml"), s.scene_text);
    written.push_back((dir / (stem + ".toml")).string());
  }
  return written;
}

std::vector<std::string> write_worst_samples(const MachineDocuments& docs,
                                             const nlohmann::json& plan,
                                             const std::vector<nlohmann::json>& samples,
                                             std::size_t k, const std::string& out_dir) {
  std::vector<nlohmann::json> worst;
  for (std::size_t i : worst_samples(samples, plan.at("nominal"), k)) worst.push_back(samples[i]);
  return write_sample_scenes(docs, plan, worst, out_dir);
}

}  // namespace flexloop::campaign
