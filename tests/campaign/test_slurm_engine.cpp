// SPDX-License-Identifier: BSD-3-Clause
// The Slurm engine's parts that need no cluster (offline/campaign/slurm_engine.hpp):
//   - the batch script: its #SBATCH lines for given options (array range and throttle, partition
//     and account only when given, the time limit rounded up to whole minutes, logs into the work
//     directory), and its command line as bash itself reads it: the script is run by bash with
//     SLURM_ARRAY_TASK_ID set and a recording program in place of flexloop, and the arguments it
//     received are compared word for word, with paths holding blanks and quotes;
//   - options Slurm could not take are InputError (nothing submitted), --sbatch-arg among them;
//   - elements requeueable with their logs appended to, --sbatch-arg lines written verbatim;
//   - the shard count: the default from the plan's evaluations, under the cluster's MaxArraySize;
//   - sbatch --parsable's "JOBID;CLUSTER" and the submission, waiting and final states through
//     fake sbatch / squeue / scontrol programs on PATH: every client after sbatch gets -M CLUSTER;
//   - the parsers on squeue / scontrol text captured from the local cluster
//     (tools/slurm/start-local-cluster, Slurm 22.05.8: an array 0-4%2 whose elements ran,
//     completed, exited 5, were cancelled, killed themselves, timed out), and sacct's documented -P
//     format (the local cluster has no accounting database, so sacct there only says it is
//     disabled).
// The engine against a real cluster: test_slurm_cluster.cpp, run by slurm_engine.sh.
#include <catch2/catch.hpp>
#include <cstdlib>

#include "common/input_error.hpp"
#include "offline/campaign/slurm_engine.hpp"
#include "tests/campaign/slurm_test_support.hpp"

using namespace flexloop::campaign;
using flexloop::campaign::test::read_file;
using flexloop::campaign::test::ScratchDir;
using flexloop::campaign::test::write_file;

namespace {

bool has_line(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line + "\n") != std::string::npos;
}

SlurmOptions options_in(const std::string& work_dir) {
  SlurmOptions o;
  o.shards = 3;
  o.flexloop_program = "/opt/flexloop/bin/flexloop";
  o.work_dir = work_dir;
  return o;
}

}  // namespace

TEST_CASE("sbatch script: array over the shards, throttle, partition and account when given",
          "[slurm]") {
  SlurmOptions o = options_in("/scratch/campaign one");
  const std::string plain = sbatch_script("/data/plan.json", o);
  CHECK(plain.rfind("#!/bin/bash\n", 0) == 0);
  CHECK(has_line(plain, "#SBATCH --array=0-2"));
  CHECK(has_line(plain, "#SBATCH --time=60"));
  CHECK(has_line(plain, "#SBATCH --cpus-per-task=1"));
  CHECK(has_line(plain, "#SBATCH --job-name=flexloop-campaign"));
  CHECK(has_line(plain, "#SBATCH --chdir=\"/scratch/campaign one\""));
  CHECK(has_line(plain, "#SBATCH --output=\"/scratch/campaign one/campaign-%A_%a.out\""));
  CHECK(has_line(plain, "#SBATCH --error=\"/scratch/campaign one/campaign-%A_%a.err\""));
  CHECK(plain.find("--partition") == std::string::npos);
  CHECK(plain.find("--account") == std::string::npos);

  o.shards = 40;
  o.array_throttle = 8;
  o.partition = "short,long";
  o.account = "proj_47";
  o.time_limit_min = 90.25;  // Slurm takes whole minutes: rounded up, never cut short
  const std::string full = sbatch_script("/data/plan.json", o);
  CHECK(has_line(full, "#SBATCH --array=0-39%8"));
  CHECK(has_line(full, "#SBATCH --partition=short,long"));
  CHECK(has_line(full, "#SBATCH --account=proj_47"));
  CHECK(has_line(full, "#SBATCH --time=91"));
  // Every directive comes before the first command (sbatch stops reading them there).
  CHECK(full.rfind("#SBATCH") < full.find("\nset -eu\n"));

  o.shards = 1;
  o.array_throttle = 0;
  CHECK(has_line(sbatch_script("/data/plan.json", o), "#SBATCH --array=0-0"));
}

TEST_CASE("sbatch script: bash hands each element its shard, paths with blanks and quotes intact",
          "[slurm]") {
  ScratchDir scratch("slurm script");
  const std::string work_dir = scratch / "work dir";
  // A recording stand-in for flexloop: one argument per line, into a file beside it.
  const std::string program = scratch / "bin dir/flex'loop";
  write_file(program, "#!/bin/sh\nprintf '%s\\n' \"$@\" > \"$(dirname \"$0\")/argv.txt\"\n", true);
  SlurmOptions o = options_in(work_dir);
  o.shards = 5;
  o.flexloop_program = program;
  const std::string plan = scratch / "plans/my plan's \"final\" $HOME.json";
  const std::string script_path = scratch / "campaign.sbatch";
  write_file(script_path, sbatch_script(plan, o));
  for (const int element : {0, 3}) {
    const std::string command =
        "SLURM_ARRAY_TASK_ID=" + std::to_string(element) + " bash '" + script_path + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    const std::string expected = "campaign\nrun\n" + plan + "\n--shard\n" +
                                 std::to_string(element) + "/5\n-o\n" + work_dir + "/shard-" +
                                 std::to_string(element) + ".jsonl\n";
    CHECK(read_file(scratch / "bin dir/argv.txt") == expected);
  }
  CHECK(slurm_shard_file(o, 3) == work_dir + "/shard-3.jsonl");
  CHECK(slurm_log_file(o, "812", 3, "err") == work_dir + "/campaign-812_3.err");
  // Outside sbatch (no array index) the script refuses to run rather than guess a shard.
  CHECK(std::system(("bash '" + script_path + "' 2>/dev/null").c_str()) != 0);
}

TEST_CASE("sbatch script: options Slurm could not take are input errors", "[slurm]") {
  using flexloop::common::InputError;
  const SlurmOptions good = options_in("/scratch/w");
  REQUIRE_NOTHROW(sbatch_script("/p.json", good));
  SlurmOptions o = good;
  o.partition = "short --account=other";
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  o = good;
  o.account = "a\nb";
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  o = good;
  o.work_dir = "/scratch/100%";  // % starts a Slurm file name pattern
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  o = good;
  o.work_dir = "/scratch/\"w\"";
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  o = good;
  o.shards = 0;
  CHECK_THROWS_WITH(sbatch_script("/p.json", o), Catch::Contains("--shards"));
  o = good;
  o.array_throttle = -1;
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  o = good;
  o.time_limit_min = 0;
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  o = good;
  o.flexloop_program = "build/flexloop";
  CHECK_THROWS_AS(sbatch_script("/p.json", o), InputError);
  CHECK_THROWS_AS(submit_slurm("/no/such/plan.json", good), InputError);
}

TEST_CASE("squeue: each element's state, other jobs and unexpanded ranges left out", "[slurm]") {
  // squeue -h -r -t all -j 5 -o "%i %T" while element 0 ran, 3 and 4 waited (throttle 2).
  const std::string running = "5_1 COMPLETED\n5_2 FAILED\n5_3 PENDING\n5_4 PENDING\n5_0 RUNNING\n";
  const std::vector<ElementState> e = parse_squeue_elements(running, "5");
  REQUIRE(e.size() == 5);
  CHECK(e[0].element == 1);
  CHECK(e[0].state == "COMPLETED");
  CHECK(e[1].element == 2);
  CHECK(e[1].state == "FAILED");
  CHECK(e[4].element == 0);
  CHECK(e[4].state == "RUNNING");
  CHECK(element_outcome(e[0]) == ElementOutcome::kSucceeded);
  CHECK(element_outcome(e[1]) == ElementOutcome::kFailed);
  CHECK(element_outcome(e[2]) == ElementOutcome::kGoing);
  CHECK(element_outcome(e[4]) == ElementOutcome::kGoing);
  // Without -r squeue folds the waiting elements into one line: not an element.
  const std::string folded = "5_1 COMPLETED\n5_2 FAILED\n5_[3-4%2] PENDING\n5_0 RUNNING\n";
  CHECK(parse_squeue_elements(folded, "5").size() == 3);
  // Job 51's elements are not job 5's.
  CHECK(parse_squeue_elements("51_0 RUNNING\n5_0 PENDING\n", "5").size() == 1);
  CHECK(parse_squeue_elements("", "5").empty());
}

TEST_CASE("scontrol show job -o: final state and exit code of each element", "[slurm]") {
  // Captured from the local cluster (array 0-4%2: element 4 killed itself with SIGKILL, 3 was
  // cancelled, 2 exited 5, 1 exited 0, 0 outran its one-minute limit); the fields after ExitCode
  // are cut, they carry nothing the engine reads.
  const std::string text =
      "JobId=5 ArrayJobId=5 ArrayTaskId=4 ArrayTaskThrottle=2 JobName=c.sbatch UserId=root(0) "
      "GroupId=root(0) MCS_label=N/A Priority=4294901758 Nice=0 Account=(null) QOS=(null) "
      "JobState=FAILED Reason=JobLaunchFailure Dependency=(null) Requeue=1 Restarts=0 "
      "BatchFlag=1 Reboot=0 ExitCode=0:9\n"
      "JobId=9 ArrayJobId=5 ArrayTaskId=3 ArrayTaskThrottle=2 JobName=c.sbatch UserId=root(0) "
      "GroupId=root(0) MCS_label=N/A Priority=4294901758 Nice=0 Account=(null) QOS=(null) "
      "JobState=CANCELLED Reason=None Dependency=(null) Requeue=1 Restarts=0 BatchFlag=1 "
      "Reboot=0 ExitCode=0:15\n"
      "JobId=8 ArrayJobId=5 ArrayTaskId=2 ArrayTaskThrottle=2 JobName=c.sbatch UserId=root(0) "
      "GroupId=root(0) MCS_label=N/A Priority=4294901758 Nice=0 Account=(null) QOS=(null) "
      "JobState=FAILED Reason=NonZeroExitCode Dependency=(null) Requeue=1 Restarts=0 "
      "BatchFlag=1 Reboot=0 ExitCode=5:0\n"
      "JobId=7 ArrayJobId=5 ArrayTaskId=1 ArrayTaskThrottle=2 JobName=c.sbatch UserId=root(0) "
      "GroupId=root(0) MCS_label=N/A Priority=4294901758 Nice=0 Account=(null) QOS=(null) "
      "JobState=COMPLETED Reason=None Dependency=(null) Requeue=1 Restarts=0 BatchFlag=1 "
      "Reboot=0 ExitCode=0:0\n"
      "JobId=6 ArrayJobId=5 ArrayTaskId=0 ArrayTaskThrottle=2 JobName=c.sbatch UserId=root(0) "
      "GroupId=root(0) MCS_label=N/A Priority=4294901758 Nice=0 Account=(null) QOS=(null) "
      "JobState=TIMEOUT Reason=TimeLimit Dependency=(null) Requeue=1 Restarts=0 BatchFlag=1 "
      "Reboot=0 ExitCode=0:15\n";
  const std::vector<ElementState> e = parse_scontrol_elements(text, "5");
  REQUIRE(e.size() == 5);
  const char* states[] = {"FAILED", "CANCELLED", "FAILED", "COMPLETED", "TIMEOUT"};
  const char* exits[] = {"0:9", "0:15", "5:0", "0:0", "0:15"};
  for (int i = 0; i < 5; ++i) {
    CHECK(e[i].element == 4 - i);
    CHECK(e[i].state == states[i]);
    CHECK(e[i].exit_code == exits[i]);
    CHECK(element_outcome(e[i]) == (i == 3 ? ElementOutcome::kSucceeded : ElementOutcome::kFailed));
  }
  // While elements wait, scontrol folds them into one record ("ArrayTaskId=3-4%2"): skipped.
  const std::string pending =
      "JobId=5 ArrayJobId=5 ArrayTaskId=3-4%2 ArrayTaskThrottle=2 JobName=c.sbatch "
      "JobState=PENDING Reason=JobArrayTaskLimit ExitCode=0:0\n";
  CHECK(parse_scontrol_elements(pending, "5").empty());
  // A completed element with a non-zero exit code (a state Slurm should not give) still fails.
  CHECK(element_outcome({1, "COMPLETED", "1:0"}) == ElementOutcome::kFailed);
}

TEST_CASE("sacct -P: states with their reasons cut, exit codes", "[slurm]") {
  const std::string text =
      "77_0|COMPLETED|0:0\n77_1|CANCELLED by 1000|0:15\n77_2|OUT_OF_MEMORY|0:125\n"
      "77_3|NODE_FAIL|0:0\n77_[4-9]|PENDING|0:0\n";
  const std::vector<ElementState> e = parse_sacct_elements(text, "77");
  REQUIRE(e.size() == 4);
  CHECK(e[0].state == "COMPLETED");
  CHECK(element_outcome(e[0]) == ElementOutcome::kSucceeded);
  CHECK(e[1].state == "CANCELLED");
  CHECK(e[1].exit_code == "0:15");
  CHECK(e[2].state == "OUT_OF_MEMORY");
  CHECK(e[3].element == 3);
  for (int i = 1; i < 4; ++i) CHECK(element_outcome(e[i]) == ElementOutcome::kFailed);
}

TEST_CASE("sbatch script: requeueable elements whose logs are appended to, and --sbatch-arg lines",
          "[slurm]") {
  SlurmOptions o = options_in("/scratch/w");
  const std::string plain = sbatch_script("/data/plan.json", o);
  // A requeued element reruns its shard (campaign run resumes it); its log keeps both attempts.
  CHECK(has_line(plain, "#SBATCH --requeue"));
  CHECK(has_line(plain, "#SBATCH --open-mode=append"));

  o.sbatch_args = {"--mem=2G",     "--qos=long", "--constraint=skylake|icelake",
                   "--gres=gpu:1", "-M other",   "--comment=\"two words\""};
  const std::string script = sbatch_script("/data/plan.json", o);
  // Each one verbatim on its own line, after the engine's own (a later line wins in sbatch), and
  // before the first command (sbatch stops reading directives there).
  std::size_t previous = script.find("#SBATCH --error=");
  for (const std::string& arg : o.sbatch_args) {
    INFO(arg);
    CHECK(has_line(script, "#SBATCH " + arg));
    const std::size_t at = script.find("#SBATCH " + arg + "\n");
    CHECK(at > previous);
    previous = at;
  }
  CHECK(previous < script.find("\nset -eu\n"));
}

TEST_CASE(
    "sbatch script: an --sbatch-arg is refused with a newline, as no option, or as one of "
    "the engine's own",
    "[slurm]") {
  using flexloop::common::InputError;
  const SlurmOptions good = options_in("/scratch/w");
  const auto refusal = [&](const std::string& arg) {
    SlurmOptions o = good;
    o.sbatch_args = {"--mem=1G", arg};
    try {
      sbatch_script("/p.json", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  // A newline would start a line of the script's own: another directive, or a command.
  const std::string newline = refusal("--mem=1G\necho owned");
  CHECK_THAT(newline, Catch::Contains("--sbatch-arg") &&
                          Catch::Contains("'--mem=1G\\necho owned'") && Catch::Contains("newline"));
  CHECK_THAT(refusal("--qos=a\rb"), Catch::Contains("--sbatch-arg"));
  CHECK_THAT(refusal("mem=1G"), Catch::Contains("not an sbatch option"));
  CHECK_THAT(refusal(""), Catch::Contains("not an sbatch option"));
  // What the engine's bookkeeping reads, and what has an option of its own; getopt_long takes a
  // long option by any prefix of its name.
  for (const std::string owned :
       {"--array=0-3", "-a 0-3", "--arr=1", "--output=x.out", "-o x", "--error=e", "--chdir=/t",
        "-D /t", "--open-mode=truncate", "--wait", "--wrap=hostname", "--partition=p", "-p p",
        "--account=a", "-A a", "--time=5", "-t 5", "--mem=1G --array=1"}) {
    INFO(owned);
    CHECK_THAT(refusal(owned), Catch::Contains("--sbatch-arg") && Catch::Contains("writes itself"));
  }
  // Options of similar names are not the engine's.
  for (const std::string own : {"--time-min=5", "--exclusive", "--export=ALL", "--mem-per-cpu=1G",
                                "-M other", "--clusters=other", "--qos=long", "--no-requeue"}) {
    INFO(own);
    CHECK(refusal(own) == "(accepted)");
  }
}

TEST_CASE("sbatch --parsable: the job id and the cluster it was sent to", "[slurm]") {
  CHECK(parse_sbatch_parsable("4242\n").id == "4242");
  CHECK(parse_sbatch_parsable("4242\n").cluster.empty());
  const SubmittedJob far = parse_sbatch_parsable("4242;far-away\n");
  CHECK(far.id == "4242");
  CHECK(far.cluster == "far-away");
  CHECK(parse_sbatch_parsable("").id.empty());
  CHECK(parse_sbatch_parsable("Submitted batch job 12\n").id.empty());
  CHECK(parse_sbatch_parsable("12;\n").id.empty());
  CHECK(parse_sbatch_parsable("12;a b\n").id.empty());

  CHECK(cluster_of_sbatch_args({"--mem=1G"}).empty());
  CHECK(cluster_of_sbatch_args({"-M other"}) == "other");
  CHECK(cluster_of_sbatch_args({"-Mother"}) == "other");
  CHECK(cluster_of_sbatch_args({"--clusters=a", "--qos=q"}) == "a");
  CHECK(cluster_of_sbatch_args({"--cluster=a", "--clusters b"}) == "b");
  CHECK(cluster_of_sbatch_args({"--mem=1G"}).empty());
}

TEST_CASE("shard count: the plan's evaluations by default, under the cluster's MaxArraySize",
          "[slurm]") {
  using flexloop::common::InputError;
  // Captured from the local cluster (Slurm 22.05.8), lines around it included.
  const std::string config =
      "Configuration data as of 2026-12-07T15:54:57\n"
      "MailType                = (null)\nMaxArraySize            = 1001\n"
      "MaxDBDMsgs              = 20008\nMaxJobCount             = 10000\n";
  CHECK(parse_max_array_size(config) == 1001);
  CHECK(parse_max_array_size("MaxArraySize = 5000\nMaxArraySize = 200\n") == 200);
  CHECK(parse_max_array_size("MaxJobCount = 10000\n") == -1);

  // The default: one shard per kEvaluationsPerShard evaluations, whatever machine submits.
  CHECK(slurm_shard_count(0, 1, 1001).shards == 1);
  CHECK(slurm_shard_count(0, kEvaluationsPerShard, 1001).shards == 1);
  CHECK(slurm_shard_count(0, kEvaluationsPerShard + 1, 1001).shards == 2);
  const ShardCount saltelli = slurm_shard_count(0, 4352, 1001);
  CHECK(saltelli.shards == 3);
  CHECK_THAT(saltelli.note, Catch::Contains("default") && Catch::Contains("4352 evaluations"));
  // MaxArraySize = N allows the indices 0 .. N-1: N elements at most.
  const ShardCount capped = slurm_shard_count(0, 1000 * kEvaluationsPerShard, 100);
  CHECK(capped.shards == 100);
  CHECK_THAT(capped.note, Catch::Contains("capped") && Catch::Contains("MaxArraySize = 100"));
  CHECK(slurm_shard_count(0, 100 * kEvaluationsPerShard, 100).shards == 100);

  // A count the user gave is kept, or refused when the cluster cannot take it.
  CHECK(slurm_shard_count(7, 1, 1001).shards == 7);
  CHECK(slurm_shard_count(7, 1, 1001).note.empty());
  CHECK(slurm_shard_count(100, 1, 100).shards == 100);
  CHECK_THROWS_AS(slurm_shard_count(101, 1, 100), InputError);
  CHECK_THROWS_WITH(slurm_shard_count(101, 1, 100),
                    Catch::Contains("--shards") && Catch::Contains("101") &&
                        Catch::Contains("MaxArraySize = 100") && Catch::Contains("at most 100"));
  CHECK_THROWS_WITH(slurm_shard_count(0, 10, 0), Catch::Contains("arrays disabled"));
}

namespace {

// PATH with a directory in front for as long as this lives (each test case runs in a process of
// its own under ctest).
class PathInFront {
 public:
  explicit PathInFront(const std::string& dir)
      : old_(std::getenv("PATH") ? std::getenv("PATH") : "") {
    ::setenv("PATH", (dir + ":" + old_).c_str(), 1);
  }
  ~PathInFront() { ::setenv("PATH", old_.c_str(), 1); }
  PathInFront(const PathInFront&) = delete;
  PathInFront& operator=(const PathInFront&) = delete;

 private:
  std::string old_;
};

// Fake Slurm clients for a job 4242 on cluster "far": each records its arguments (one per line,
// then a line "--") into calls.txt beside it. sbatch keeps the script it was given; scontrol
// shows a configuration with MaxArraySize = 4 and every element COMPLETED, as squeue does.
void write_fake_clients(const std::string& bin, int elements) {
  const std::string record =
      "#!/bin/bash\n{ echo \"$(basename \"$0\")\"; printf '%s\\n' \"$@\"; "
      "echo --; } >> \"$(dirname \"$0\")/calls.txt\"\n";
  write_file(bin + "/sbatch",
             record + "cp \"${@: -1}\" \"$(dirname \"$0\")/submitted.sbatch\"\necho '4242;far'\n",
             true);
  std::string squeue = record, scontrol = record;
  scontrol += "if [ \"$*\" = '-M far show job 4242 -o' ]; then\n";
  for (int k = 0; k < elements; ++k) {
    squeue += "echo '4242_" + std::to_string(k) + " COMPLETED'\n";
    scontrol += "  echo 'JobId=" + std::to_string(5000 + k) +
                " ArrayJobId=4242 ArrayTaskId=" + std::to_string(k) +
                " JobState=COMPLETED Reason=None ExitCode=0:0'\n";
  }
  scontrol +=
      "elif [ \"$*\" = 'show config' ] || [ \"$*\" = '-M far show config' ]; then\n  echo "
      "'MaxArraySize            = 4'\n"
      "else\n  echo \"fake scontrol: $*\" >&2; exit 1\nfi\n";
  write_file(bin + "/squeue", squeue, true);
  write_file(bin + "/scontrol", scontrol, true);
}

// A scratch directory with the fake clients first on PATH, a plan, and options for it.
struct FakeSlurm {
  ScratchDir scratch{"slurm fake clients"};
  std::string bin = scratch / "bin", plan = scratch / "plan.json";
  SlurmOptions options = options_in(scratch / "work");
  explicit FakeSlurm(int elements) {
    write_fake_clients(bin, elements);
    write_file(plan, "{}\n");
  }
  std::string calls() const { return read_file(bin + "/calls.txt"); }

 private:
  PathInFront path_{bin};
};

}  // namespace

TEST_CASE(
    "submit_slurm: a job on another cluster is followed there (-M), MaxArraySize caps the "
    "default",
    "[slurm]") {
  FakeSlurm fake(4);
  SlurmOptions& o = fake.options;
  o.shards = 0;                               // the default: 10 shards for these evaluations,
  o.evaluations = 10 * kEvaluationsPerShard;  // capped at MaxArraySize = 4
  o.sbatch_args = {"--mem=1G", "-M far"};
  for (int k = 0; k < 4; ++k) write_file(slurm_shard_file(o, k), "");

  const std::vector<std::string> files = submit_slurm(fake.plan, o);
  CHECK(files.size() == 4);
  const std::string script = read_file(fake.bin + "/submitted.sbatch");
  CHECK(has_line(script, "#SBATCH --array=0-3"));
  CHECK(has_line(script, "#SBATCH --mem=1G"));
  CHECK(has_line(script, "#SBATCH -M far"));
  const std::string calls = fake.calls();
  INFO(calls);
  // MaxArraySize of the cluster the job goes to; the job found there by the cluster sbatch named.
  CHECK(calls.find("scontrol\n-M\nfar\nshow\nconfig\n--\n") != std::string::npos);
  CHECK(calls.find("sbatch\n--parsable\n") != std::string::npos);
  CHECK(calls.find("squeue\n-M\nfar\n-h\n-r\n-t\nall\n-j\n4242\n") != std::string::npos);
  CHECK(calls.find("scontrol\n-M\nfar\nshow\njob\n4242\n-o\n") != std::string::npos);
  CHECK(calls.find("squeue\n-h") == std::string::npos);
  CHECK(calls.find("scontrol\nshow\njob") == std::string::npos);
}

TEST_CASE("submit_slurm: --shards above the cluster's MaxArraySize is refused before sbatch",
          "[slurm]") {
  FakeSlurm fake(4);
  fake.options.shards = 5;
  CHECK_THROWS_WITH(submit_slurm(fake.plan, fake.options),
                    Catch::Contains("--shards") && Catch::Contains("MaxArraySize = 4"));
  const std::string calls = fake.calls();
  CHECK(calls.find("scontrol\nshow\nconfig\n--\n") != std::string::npos);
  CHECK(calls.find("sbatch") == std::string::npos);
}
