// SPDX-License-Identifier: BSD-3-Clause
// Shards (offline/campaign/shard_run.hpp), their merge (shard_merge.hpp) and the plan file
// (plan_file.hpp): a shard killed mid-line and rerun ends with the bytes of an uninterrupted
// run and computes only what was missing; a file of another plan is refused with file:line;
// the merged samples are the same bytes whatever the number of shards; missing samples are
// listed; an edited plan and a changed scene are refused.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "common/input_error.hpp"
#include "common/sha256.hpp"
#include "offline/campaign/campaign_plan.hpp"
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
using flexloop::campaign::GrowingLineCount;
using flexloop::campaign::index_ranges;
using flexloop::campaign::inverse_cdf;
using flexloop::campaign::kPlanFormat;
using flexloop::campaign::kPlanVersion;
using flexloop::campaign::lock_shard;
using flexloop::campaign::make_plan;
using flexloop::campaign::merge_shards;
using flexloop::campaign::MergedSamples;
using flexloop::campaign::parse_shard;
using flexloop::campaign::plan_id_of;
using flexloop::campaign::PlanRequest;
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
  // One per process: CTest runs this file's cases side by side.
  fs::path path =
      fs::temp_directory_path() / ("flexloop_test_shards_" + std::to_string(::getpid()));
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

TEST_CASE("a second writer of a shard is refused naming the holder, and the file is untouched",
          "[campaign][shard]") {
  // Issue 54, 2.1: two writers interleaved lines (52 torn of 3717). A child process holds the
  // shard's lock, as a first `campaign run` would; this process is the second writer.
  TempDir dir;
  const fs::path file = dir.path / "b.jsonl";
  run_shard(file.string(), "plan-a", parse_shard("0/2"), kEvaluations,
            [](long i) { return line_of("plan-a", i); });
  const std::string before = bytes_of(file);
  int locked[2], release[2];
  REQUIRE(::pipe(locked) == 0);
  REQUIRE(::pipe(release) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    ::close(locked[0]), ::close(release[1]);  // else its own write end keeps the read below open
    const auto held = lock_shard(file.string());
    char c = 1;
    (void)!::write(locked[1], &c, 1);
    (void)!::read(release[0], &c, 1);  // until the parent closes its end
    ::_exit(0);
  }
  ::close(locked[1]), ::close(release[0]);
  char c = 0;
  REQUIRE(::read(locked[0], &c, 1) == 1);
  CHECK_THAT(shard_refusal([&] { (void)lock_shard(file.string()); }),
             Contains(file.string() + ": another run is writing this shard (pid " +
                      std::to_string(child) + " holds its lock)"));
  CHECK(bytes_of(file) == before);
  ::close(release[1]);
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  ::close(locked[0]);
  // The holder gone, its lock went with it.
  CHECK(lock_shard(file.string()) != nullptr);
}

TEST_CASE("a damaged tail is cut with a note, a damaged line before good ones is refused",
          "[campaign][shard]") {
  TempDir dir;
  const fs::path file = dir.path / "crashed.jsonl";
  run_shard(file.string(), "plan-a", parse_shard("0/1"), 3,
            [](long i) { return line_of("plan-a", i); });
  const std::string good = bytes_of(file);
  // What a crash can leave: a zero-filled hole and a torn line after the good ones.
  {
    std::ofstream(file, std::ios::binary | std::ios::app) << std::string(40, '\0') << "\n{\"plan_i";
  }
  std::string note;
  CHECK(completed_indices(file.string(), "plan-a", parse_shard("0/1"), 3, &note) ==
        std::vector<long>{0, 1, 2});
  CHECK(bytes_of(file) == good);
  CHECK_THAT(note, Contains("cut 49 bytes of a damaged tail after line 3"));
  // A damaged line with a good one after it is no tail: refused, the file kept.
  const std::string middle =
      good.substr(0, good.find('\n') + 1) + "{torn\n" + good.substr(good.find('\n') + 1);
  { std::ofstream(file, std::ios::binary) << middle; }
  CHECK_THAT(
      shard_refusal([&] { completed_indices(file.string(), "plan-a", parse_shard("0/1"), 3); }),
      Contains(file.string() + ":2: not a JSON line"));
  CHECK(bytes_of(file) == middle);
}

TEST_CASE(
    "a sample that kills its process is written as crashed by the next run, a Ctrl-C's is not",
    "[campaign][shard]") {
  // Issue 54, 2.2: a segfault or an OOM kill at index i killed every rerun at i.
  // (tests/campaign/slurm_campaign.sh: one SIGKILL mid-shard, the rerun's bytes unchanged.)
  TempDir dir;
  const Shard shard = parse_shard("1/3");  // 1, 4, 7, ..., 22
  const auto run_child_dying_at_7 = [&](const fs::path& file, int signal_number) {
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      run_shard(file.string(), "plan-a", shard, kEvaluations, [&](long i) {
        if (i == 7) ::raise(signal_number);
        return line_of("plan-a", i);
      });
      ::_exit(0);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal_number);
  };
  const fs::path crashed = dir.path / "crashed.jsonl";
  // SIGKILL as the OOM killer sends it (a SIGSEGV alike, but the sanitizers catch that one and
  // exit instead). One death may be the machine's: the next run computes sample 7 again.
  run_child_dying_at_7(crashed, SIGKILL);
  CHECK(complete_lines(crashed.string()) == 2);
  CHECK(fs::exists(crashed.string() + ".attempt"));
  run_child_dying_at_7(crashed, SIGKILL);  // the second death in sample 7: the sample's
  CHECK(complete_lines(crashed.string()) == 2);
  const ShardRunResult rerun = run_shard(
      crashed.string(), "plan-a", shard, kEvaluations, [](long i) { return line_of("plan-a", i); },
      [](long i, const std::string& status) {
        return nlohmann::json{{"plan_id", "plan-a"}, {"index", i}, {"status", status}};
      });
  CHECK(rerun.already == 2);
  CHECK(rerun.crashed == 1);
  CHECK(rerun.computed == 5);
  CHECK_FALSE(fs::exists(crashed.string() + ".attempt"));
  std::ifstream in(crashed);
  std::string line;
  for (int k = 0; k < 3; ++k) std::getline(in, line);
  const nlohmann::json third = nlohmann::json::parse(line);
  CHECK(third["index"] == 7);
  CHECK_THAT(third["status"].get<std::string>(), Contains("error: crashed: two runs died"));

  // SIGTERM (a scheduler's cancel, a Ctrl-C's SIGINT alike) is not the sample's fault: the
  // marker goes with the process, and the rerun computes sample 7.
  const fs::path cancelled = dir.path / "cancelled.jsonl";
  run_child_dying_at_7(cancelled, SIGTERM);
  CHECK_FALSE(fs::exists(cancelled.string() + ".attempt"));
  const ShardRunResult resumed = run_shard(cancelled.string(), "plan-a", shard, kEvaluations,
                                           [](long i) { return line_of("plan-a", i); });
  CHECK(resumed.crashed == 0);
  CHECK(resumed.computed == 6);
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

TEST_CASE("shards computed by two builds are not merged, both builds named", "[campaign][shard]") {
  TempDir dir;
  const nlohmann::json plan{{"plan_id", "plan-a"}, {"evaluations", kEvaluations}};
  const auto built_by = [](const char* build) {
    return [build](long i) {
      nlohmann::json line = line_of("plan-a", i);
      line["flexloop"] = {{"version", "0.1.0"}, {"build", build}};
      return line;
    };
  };
  const std::string a = (dir.path / "a.jsonl").string(), b = (dir.path / "b.jsonl").string();
  run_shard(a, "plan-a", {0, 2}, kEvaluations, built_by("1111aaaa2222bbbb"));
  run_shard(b, "plan-a", {1, 2}, kEvaluations, built_by("3333cccc4444dddd"));
  CHECK_THAT(shard_refusal([&] {
               merge_shards(plan, {a, b});
             }),
             Contains(b + ":1: computed by flexloop") && Contains("3333cccc4444dddd") &&
                 Contains(a + ":1 by") && Contains("1111aaaa2222bbbb"));
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

TEST_CASE(
    "a plan holds the controller file and the nominal artefact by hash, and run refuses a change",
    "[campaign][plan]") {
  // Issue 54, 2.3: a state-space controller file edited after planning went unseen.
  TempDir dir;
  for (const char* folder : {"scenes", "models", "controllers"})
    fs::create_directories(dir.path / folder);
  for (const char* file :
       {"scenes/metrology_frame_lqg.toml", "scenes/metrology_frame_uncertain.toml",
        "models/metrology_frame.toml", "controllers/metrology_frame_lqg.json"})
    fs::copy_file(fs::path("tools") / file, dir.path / file);
  PlanRequest r;
  r.scene = (dir.path / "scenes/metrology_frame_lqg.toml").string();
  r.uncertain = (dir.path / "scenes/metrology_frame_uncertain.toml").string();
  r.n = 2;
  r.grid_points = 20;
  const nlohmann::json plan = make_plan(r);
  const fs::path controller = dir.path / "controllers/metrology_frame_lqg.json";
  CHECK(plan["controller_file"] == fs::absolute(controller).lexically_normal().string());
  CHECK(plan["controller_file_sha256"] == flexloop::common::file_sha256(controller.string()));
  require_plan_inputs_unchanged(plan, "plan.json");

  nlohmann::json other_build = plan;  // as another flexloop would have built the nominal loop
  other_build["nominal_artefact_sha256"] = std::string(64, '0');
  CHECK_THAT(
      shard_refusal([&] { require_plan_inputs_unchanged(other_build, "plan.json"); }),
      Contains("the nominal loop artefact") &&
          Contains("(SHA-256 0000000000000000 in "
                   "the plan, " +
                   plan["nominal_artefact_sha256"].get<std::string>().substr(0, 16) + " now)"));
  std::ofstream(controller, std::ios::app) << "\n";  // the same JSON, another file
  CHECK_THAT(
      shard_refusal([&] { require_plan_inputs_unchanged(plan, "plan.json"); }),
      Contains("plan.json: the controller file " + plan["controller_file"].get<std::string>() +
               " changed since the plan was made"));
}

TEST_CASE("an engine's progress reads only what a shard appended since it last looked",
          "[campaign][shard]") {
  // Issue 54, 2.5: the local engine read every shard whole every 250 ms.
  TempDir dir;
  const std::string file = (dir.path / "growing.jsonl").string();
  GrowingLineCount count;
  CHECK(count.lines(file) == 0);  // not there yet
  std::string text;
  for (long i = 0; i < kEvaluations; ++i) {
    text += line_of("plan-a", i).dump() + "\n";
    { std::ofstream(file, std::ios::binary) << text << "{\"torn"; }
    CHECK(count.lines(file) == i + 1);
    CHECK(count.lines(file) == complete_lines(file));
  }
  // Cut back (a damaged tail removed by the next run): counted again from the start.
  { std::ofstream(file, std::ios::binary) << text.substr(0, text.find('\n') + 1); }
  CHECK(count.lines(file) == 1);
}

TEST_CASE(
    "the merge reads each line once: a repeated index of the same bytes is taken once, "
    "of other bytes or torn refused with its line",
    "[campaign][shard]") {
  // Issue 54, 2.5: the merge keeps where each line is, not the line; a repeat is compared with
  // the first line's bytes read again, and the places named are the lines'.
  TempDir dir;
  const nlohmann::json plan{{"plan_id", "plan-a"}, {"evaluations", kEvaluations}};
  const std::string whole = (dir.path / "whole.jsonl").string(),
                    again = (dir.path / "again.jsonl").string();
  run_shard(whole, "plan-a", {0, 1}, kEvaluations, [](long i) { return line_of("plan-a", i); });
  const std::string text = bytes_of(whole);
  { std::ofstream(again, std::ios::binary) << text.substr(text.find('\n') + 1); }  // 1..22
  std::vector<long> taken;
  const auto lines = flexloop::campaign::merge_shards(
      plan, {whole, again}, [&](long index, const nlohmann::json&) { taken.push_back(index); });
  CHECK(taken.size() == kEvaluations);  // each index once, in the order of the files
  CHECK(taken.front() == 0);
  CHECK(taken.back() == kEvaluations - 1);
  CHECK(lines.line(7) == line_of("plan-a", 7).dump() + "\n");
  CHECK(lines.place(7) == whole + ":8");

  nlohmann::json changed = line_of("plan-a", 7);
  changed["spectral_radius"] = 0.5;
  const std::string other = (dir.path / "other.jsonl").string();
  {
    std::ofstream(other, std::ios::binary) << line_of("plan-a", 3).dump() << "\n"
                                           << changed.dump() << "\n";
  }
  CHECK_THAT(shard_refusal([&] {
               merge_shards(plan, {whole, other});
             }),
             Contains(other + ":2: index 7 differs from " + whole + ":8"));
  { std::ofstream(other, std::ios::binary) << line_of("plan-a", 3).dump() << "\n{\"torn"; }
  CHECK_THAT(shard_refusal([&] {
               merge_shards(plan, {whole, other});
             }),
             Contains(other + ":2: a torn last line"));
}
