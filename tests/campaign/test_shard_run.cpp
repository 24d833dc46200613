// Shards (offline/campaign/shard_run.hpp), their merge (shard_merge.hpp) and the plan file
// (plan_file.hpp): a shard killed mid-line and rerun ends with the bytes of an uninterrupted
// run and computes only what was missing; a file of another plan is refused with file:line;
// the merged samples are the same bytes whatever the number of shards; missing samples are
// listed; an edited plan and a changed scene are refused.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "offline/campaign/distributions.hpp"
#include "offline/campaign/plan_file.hpp"
#include "offline/campaign/shard_merge.hpp"
#include "offline/campaign/shard_run.hpp"
#include "offline/scene/loop_input.hpp"

namespace {

// Using-declarations, not directives: the area's test files share unity batches.
using Catch::Matchers::Contains;
using flexloop::campaign::complete_lines;
using flexloop::campaign::completed_indices;
using flexloop::campaign::Distribution;
using flexloop::campaign::DistributionKind;
using flexloop::campaign::index_ranges;
using flexloop::campaign::inverse_cdf;
using flexloop::campaign::kPlanFormat;
using flexloop::campaign::kPlanVersion;
using flexloop::campaign::merge_shards;
using flexloop::campaign::MergedSamples;
using flexloop::campaign::parse_shard;
using flexloop::campaign::plan_id_of;
using flexloop::campaign::read_plan;
using flexloop::campaign::require_plan_inputs_unchanged;
using flexloop::campaign::run_shard;
using flexloop::campaign::Shard;
using flexloop::campaign::shard_indices;
using flexloop::campaign::ShardRunResult;
using flexloop::campaign::with_plan_id;
using flexloop::common::InputError;
namespace fs = std::filesystem;

constexpr long kEvaluations = 23;

// A line as a sample's would be: a pure function of the plan id and the index (values from an
// inverse CDF, so the numbers need their full precision to round-trip).
nlohmann::json line_of(const std::string& plan_id, long index) {
  Distribution d;
  d.kind = DistributionKind::kNormal, d.mean = 5.26e6, d.sd = 2.6e5;
  const double u = (static_cast<double>(index) + 0.5) / kEvaluations;
  return {{"plan_id", plan_id},
          {"index", index},
          {"parameters", {{"element.4.stiffness", inverse_cdf(d, u)}}},
          {"status", "stable"},
          {"spectral_radius", 0.9 + 1e-3 * u}};
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct TempDir {
  fs::path path = fs::temp_directory_path() / "flexloop_test_shards";
  TempDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

std::string shard_refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("not refused");
  return "";
}

}  // namespace

TEST_CASE("shard K of M holds the indices i % M == K", "[campaign][shard]") {
  CHECK(shard_indices(parse_shard("1/4"), 10) == std::vector<long>{1, 5, 9});
  CHECK(shard_indices(parse_shard("0/1"), 3) == std::vector<long>{0, 1, 2});
  for (const char* bad : {"4/4", "-1/3", "1/0", "1-3", "1/3x", ""})
    CHECK_THROWS_AS(parse_shard(bad), InputError);
}

TEST_CASE("a shard killed mid-line and rerun gives the uninterrupted run's bytes",
          "[campaign][shard]") {
  TempDir dir;
  const Shard shard = parse_shard("1/3");
  const fs::path whole = dir.path / "whole.jsonl", killed = dir.path / "killed.jsonl";
  long calls = 0;
  auto f = [&](long i) {
    ++calls;
    return line_of("plan-a", i);
  };
  const ShardRunResult first = run_shard(whole.string(), "plan-a", shard, kEvaluations, f);
  CHECK(first.computed == 8);  // 1, 4, ..., 19, 22
  const std::string reference = bytes_of(whole);
  CHECK(complete_lines(whole.string()) == 8);

  // Killed while writing the fourth line: three lines and a torn one.
  const std::size_t third_end = [&] {
    std::size_t at = 0;
    for (int i = 0; i < 3; ++i) at = reference.find('\n', at) + 1;
    return at;
  }();
  { std::ofstream(killed, std::ios::binary) << reference.substr(0, third_end + 17); }
  calls = 0;
  const ShardRunResult rerun = run_shard(killed.string(), "plan-a", shard, kEvaluations, f);
  CHECK(rerun.already == 3);
  CHECK(rerun.computed == 5);
  CHECK(calls == 5);
  CHECK(bytes_of(killed) == reference);

  // Complete: a third run computes nothing and changes nothing.
  calls = 0;
  CHECK(run_shard(killed.string(), "plan-a", shard, kEvaluations, f).computed == 0);
  CHECK(calls == 0);
  CHECK(bytes_of(killed) == reference);
}

TEST_CASE("a shard file of another plan or shard is refused with file:line", "[campaign][shard]") {
  TempDir dir;
  const fs::path file = dir.path / "shard-0.jsonl";
  run_shard(file.string(), "plan-a", parse_shard("0/2"), kEvaluations,
            [](long i) { return line_of("plan-a", i); });
  const std::string before = bytes_of(file);
  CHECK_THAT(shard_refusal([&] {
               run_shard(file.string(), "plan-b", parse_shard("0/2"), kEvaluations,
                         [](long i) { return line_of("plan-b", i); });
             }),
             Contains(file.string() + ":1: this line belongs to another plan (plan_id plan-a"));
  CHECK_THAT(shard_refusal([&] {
               completed_indices(file.string(), "plan-a", parse_shard("1/2"), kEvaluations);
             }),
             Contains(file.string() + ":1: index 0 is not one of shard 1/2"));
  CHECK(bytes_of(file) == before);  // nothing written on shard_refusal
}

TEST_CASE("merged shards are the same bytes whatever the sharding, and missing samples are listed",
          "[campaign][shard]") {
  TempDir dir;
  const nlohmann::json plan{{"plan_id", "plan-a"}, {"evaluations", kEvaluations}};
  auto shards_of = [&](long m) {
    std::vector<std::string> files;
    for (long k = 0; k < m; ++k) {
      files.push_back((dir.path / ("m" + std::to_string(m) + "-" + std::to_string(k))).string());
      run_shard(files.back(), "plan-a", {k, m}, kEvaluations,
                [](long i) { return line_of("plan-a", i); });
    }
    return files;
  };
  const MergedSamples one = merge_shards(plan, shards_of(1));
  const MergedSamples five = merge_shards(plan, shards_of(5));
  CHECK(one.jsonl == five.jsonl);
  REQUIRE(five.samples.size() == kEvaluations);
  for (long i = 0; i < kEvaluations; ++i) CHECK(five.samples[i]["index"] == i);
  // The numbers read back exactly (full round-trip precision).
  CHECK(five.samples[7]["parameters"]["element.4.stiffness"].get<double>() ==
        line_of("plan-a", 7)["parameters"]["element.4.stiffness"].get<double>());

  std::vector<std::string> files = shards_of(5);
  files.erase(files.begin() + 3);  // shard 3/5: 3, 8, 13, 18
  CHECK_THAT(shard_refusal([&] { merge_shards(plan, files); }),
             Contains("4 of 23 samples missing: 3, 8, 13, 18"));
  CHECK(index_ranges({0, 1, 2, 5, 7, 8}) == "0-2, 5, 7-8");

  const fs::path other = dir.path / "other.jsonl";
  run_shard(other.string(), "plan-b", {0, 1}, kEvaluations,
            [](long i) { return line_of("plan-b", i); });
  CHECK_THAT(shard_refusal([&] {
               merge_shards(plan, {shards_of(1)[0], other.string()});
             }),
             Contains(other.string() + ":1: this line belongs to another plan (plan_id plan-b"));
}

TEST_CASE("a plan's id is its content's hash, and an edited plan and changed inputs are refused",
          "[campaign][plan]") {
  TempDir dir;
  const fs::path scene = dir.path / "scene.toml", model = dir.path / "model.toml",
                 u = dir.path / "U.toml";
  for (const auto& f : {scene, model, u}) std::ofstream(f) << "# " << f.filename() << "\n";
  nlohmann::json plan{{"format", kPlanFormat},
                      {"version", kPlanVersion},
                      {"scene", scene.string()},
                      {"model", model.string()},
                      {"uncertain", u.string()},
                      {"n", 10},
                      {"seed", 1}};
  for (const auto& [key, f] : {std::pair{"scene_sha256", scene}, std::pair{"model_sha256", model},
                               std::pair{"uncertain_sha256", u}})
    plan[key] = flexloop::common::file_sha256(f.string());
  plan = with_plan_id(plan);
  const fs::path path = dir.path / "plan.json";
  std::ofstream(path) << plan.dump(1);
  CHECK(read_plan(path.string()) == plan);
  CHECK(plan["plan_id"].get<std::string>().size() == 64);
  nlohmann::json other = plan;
  other["seed"] = 2;
  CHECK(plan_id_of(other) != plan["plan_id"]);
  require_plan_inputs_unchanged(plan, path.string());

  std::ofstream(path) << other.dump(1);  // edited by hand: its id no longer matches
  CHECK_THAT(shard_refusal([&] { read_plan(path.string()); }),
             Contains("the plan's content does not match its plan_id"));
  std::ofstream(model, std::ios::app) << "# edited\n";
  CHECK_THAT(shard_refusal([&] { require_plan_inputs_unchanged(plan, path.string()); }),
             Contains("the model file " + model.string() + " changed since the plan was made"));
  std::ofstream(path) << "{\"format\": \"something else\"}";
  CHECK_THAT(shard_refusal([&] { read_plan(path.string()); }), Contains("not a campaign plan"));
}
