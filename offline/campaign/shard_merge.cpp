#include "offline/campaign/shard_merge.hpp"

#include <fstream>
#include <map>

#include "common/input_error.hpp"
#include "common/toml_reader.hpp"
#include "offline/campaign/shard_run.hpp"

namespace flexloop::campaign {

namespace {

struct ShardLine {
  std::string text, place;
  nlohmann::json json;
};

void read_shard(const std::string& file, const nlohmann::json& plan,
                std::map<long, ShardLine>& lines) {
  const std::string text = common::read_input_file(file, "shard file");
  const std::string plan_id = plan.at("plan_id").get<std::string>();
  const long evaluations = plan.at("evaluations").get<long>();
  std::size_t start = 0;
  long number = 0;
  for (std::size_t end; start < text.size(); start = end + 1) {
    end = text.find('\n', start);
    const std::string place = file + ":" + std::to_string(++number);
    if (end == std::string::npos)
      throw common::InputError(place,
                               "a torn last line (its run was killed): run the shard again "
                               "(`flexloop campaign run` completes it)");
    ShardLine line{text.substr(start, end - start + 1), place,
                   plan_line(text.substr(start, end - start), place, plan_id)};
    const long index = line.json.value("index", -1L);
    if (index < 0 || index >= evaluations)
      throw common::InputError(place, "index " + std::to_string(index) +
                                          " is not in the plan (0.." +
                                          std::to_string(evaluations - 1) + ")");
    const auto [it, fresh] = lines.emplace(index, line);
    if (!fresh && it->second.text != line.text)
      throw common::InputError(
          place, "index " + std::to_string(index) + " differs from " + it->second.place);
  }
}

}  // namespace

std::string index_ranges(const std::vector<long>& sorted, std::size_t at_most) {
  std::string out;
  std::size_t ranges = 0;
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    while (j + 1 < sorted.size() && sorted[j + 1] == sorted[j] + 1) ++j;
    if (++ranges > at_most) return out + ", ...";
    out += (out.empty() ? "" : ", ") + std::to_string(sorted[i]) +
           (j > i ? "-" + std::to_string(sorted[j]) : "");
    i = j + 1;
  }
  return out;
}

namespace {

// One build computed every line (each says which: "flexloop" {version, build}); lines of two
// builds may differ in their last bits, so a campaign's are not pooled.
void require_one_build(const std::map<long, ShardLine>& lines) {
  const ShardLine* first = nullptr;
  for (const auto& [index, line] : lines) {
    const nlohmann::json build = line.json.value("flexloop", nlohmann::json());
    if (!first) {
      first = &line;
    } else if (build != first->json.value("flexloop", nlohmann::json())) {
      throw common::InputError(
          line.place, "computed by flexloop " + build.dump() + ", but " + first->place + " by " +
                          first->json.value("flexloop", nlohmann::json()).dump() +
                          ": a campaign's samples come from one build; run its shards again "
                          "with one flexloop");
    }
  }
}

}  // namespace

MergedSamples merge_shards(const nlohmann::json& plan, const std::vector<std::string>& files) {
  std::map<long, ShardLine> lines;
  for (const auto& f : files) read_shard(f, plan, lines);
  require_one_build(lines);
  const long evaluations = plan.at("evaluations").get<long>();
  std::vector<long> missing;
  for (long i = 0; i < evaluations; ++i)
    if (!lines.count(i)) missing.push_back(i);
  if (!missing.empty())
    throw common::InputError(
        "plan " + plan.at("plan_id").get<std::string>().substr(0, 12),
        std::to_string(missing.size()) + " of " + std::to_string(evaluations) +
            " samples missing: " + index_ranges(missing) +
            " (run the shards that hold them again with `flexloop campaign run`, or pass their "
            "files)");
  MergedSamples m;
  for (auto& [index, line] : lines) {
    m.jsonl += line.text;
    m.samples.push_back(std::move(line.json));
  }
  return m;
}

}  // namespace flexloop::campaign
