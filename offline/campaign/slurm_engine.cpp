// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/slurm_engine.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/input_error.hpp"

extern char** environ;

namespace flexloop::campaign {
namespace {

using common::InputError;
using Clock = std::chrono::steady_clock;

// Slurm names (partition, account) are words: letters, digits, '_', '-', '.', and ',' between
// several partitions. Anything else would change the meaning of the #SBATCH line.
void check_slurm_name(const std::string& option, const std::string& value) {
  for (const char c : value)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
          c == ','))
      throw InputError(option, "'" + value + "' is not a Slurm name (letters, digits, _ - . ,)");
}

// A path in an #SBATCH line is written in double quotes, which sbatch removes; '%' would be read
// as one of Slurm's file name patterns (%A, %a, ...), a quote or backslash would end the value.
void check_directive_path(const std::string& option, const std::string& path) {
  if (path.empty() || path.front() != '/')
    throw InputError(option, "'" + path + "' is not an absolute path");
  for (const char c : path)
    if (c == '%' || c == '"' || c == '\\' || std::iscntrl(static_cast<unsigned char>(c)))
      throw InputError(option, "'" + path +
                                   "' holds a character Slurm's #SBATCH lines cannot carry "
                                   "(% \" \\ or a control character)");
}

// A value as an error message shows it: a newline as \n, so that the message stays one line.
std::string printable(const std::string& value) {
  std::string shown;
  for (const char c : value) {
    if (c == '\n')
      shown += "\\n";
    else if (c == '\r')
      shown += "\\r";
    else if (std::iscntrl(static_cast<unsigned char>(c)))
      shown += '?';
    else
      shown += c;
  }
  return "'" + shown + "'";
}

std::vector<std::string> blank_separated_words(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

// The option a word of an #SBATCH line sets that the engine writes itself (its bookkeeping reads
// the array, the logs, the directory; sbatch --parsable and no --wait are how it submits), or
// empty. A long option is matched as getopt_long matches it: by any prefix of its name.
std::string engine_option_in(const std::string& word) {
  static const char* const kLong[] = {"array",     "output",   "error", "chdir",
                                      "open-mode", "parsable", "wait",  "wrap",
                                      "partition", "account",  "time"};
  static const std::string kShort = "aoeDWpAt";
  if (word.rfind("--", 0) == 0) {
    const std::string name = word.substr(2, word.find('=') - 2);
    for (const std::string owned : kLong)
      if (!name.empty() && owned.rfind(name, 0) == 0) return "--" + owned;
    return "";
  }
  if (word.size() >= 2 && word[0] == '-' && kShort.find(word[1]) != std::string::npos)
    return word.substr(0, 2);
  return "";
}

// An --sbatch-arg becomes one #SBATCH line as it is: it must be an option, one line, and leave
// the engine's own options alone (partition, account and time have options of their own).
void check_sbatch_arg(const std::string& arg) {
  if (arg.empty() || arg.front() != '-')
    throw InputError("--sbatch-arg", printable(arg) +
                                         " is not an sbatch option (one that starts with '-', as "
                                         "--mem=4G or -M other)");
  if (std::any_of(arg.begin(), arg.end(),
                  [](char c) { return std::iscntrl(static_cast<unsigned char>(c)); }))
    throw InputError("--sbatch-arg", printable(arg) +
                                         " holds a newline or another control character: each "
                                         "value is written as one #SBATCH line");
  for (const std::string& word : blank_separated_words(arg)) {
    const std::string owned = engine_option_in(word);
    if (!owned.empty())
      throw InputError("--sbatch-arg",
                       printable(arg) + " sets " + owned +
                           ", which flexloop writes itself (use --partition, --account, "
                           "--time-limit, --shards, --array-throttle, --work-dir)");
  }
}

void check_options(const SlurmOptions& o) {
  if (o.shards < 1)
    throw InputError("--shards", "must be at least 1 (got " + std::to_string(o.shards) + ")");
  if (o.array_throttle < 0) throw InputError("array throttle", "must be 0 (none) or positive");
  if (!(o.time_limit_min > 0) || !std::isfinite(o.time_limit_min))
    throw InputError("time limit", "must be a positive number of minutes");
  check_slurm_name("--partition", o.partition);
  check_slurm_name("--account", o.account);
  if (o.flexloop_program.empty() || o.flexloop_program.front() != '/')
    throw InputError("flexloop program", "'" + o.flexloop_program + "' is not an absolute path");
  check_directive_path("work directory", o.work_dir);
  for (const std::string& arg : o.sbatch_args) check_sbatch_arg(arg);
}

// 'text' for a POSIX shell: everything literal, a quote as '\''.
std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct ProgramResult {
  int status = -1;  // exit status, or 128 + signal
  std::string out, err;
};

// Read both pipes to their end (poll: neither child pipe may fill while we wait on the other).
void drain(int out_fd, int err_fd, ProgramResult& r) {
  pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  std::string* sinks[2] = {&r.out, &r.err};
  int open_count = 2;
  char buffer[4096];
  while (open_count > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        sinks[i]->append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_count;
      }
    }
  }
}

// Run a program (looked up on PATH) with these arguments, stdin from /dev/null, and capture what
// it writes. A program that cannot be started is std::runtime_error.
ProgramResult run_program(const std::vector<std::string>& argv) {
  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  ProgramResult r;
  if (rc != 0) {
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    throw std::runtime_error("cannot run '" + argv[0] + "' (is Slurm's client installed and on " +
                             "PATH?): " + std::strerror(rc));
  }
  drain(out_pipe[0], err_pipe[0], r);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

std::string trimmed(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

// The last `count` lines of a (log) file, or a note that it is missing or empty.
std::string last_lines(const std::string& path, std::size_t count) {
  std::ifstream in(path);
  if (!in) return "  (" + path + ": not written)\n";
  std::deque<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    lines.push_back(line);
    if (lines.size() > count) lines.pop_front();
  }
  if (lines.empty()) return "  (" + path + ": empty)\n";
  std::string text;
  for (const std::string& line : lines) text += "  | " + line + "\n";
  return text;
}

SubmittedJob submit_script(const std::string& script_path) {
  const ProgramResult r = run_program({"sbatch", "--parsable", script_path});
  const SubmittedJob job = parse_sbatch_parsable(r.out);
  if (r.status != 0 || job.id.empty())
    throw std::runtime_error("sbatch " + script_path + " failed (status " +
                             std::to_string(r.status) + "): " + trimmed(r.err + r.out));
  return job;
}

// A Slurm client's arguments for this job's cluster: -M CLUSTER right after the program's name.
std::vector<std::string> on_cluster(std::vector<std::string> argv, const std::string& cluster) {
  if (!cluster.empty()) argv.insert(argv.begin() + 1, {"-M", cluster});
  return argv;
}

// "4242", or "4242 on cluster far" for a job on another cluster.
std::string job_text(const SubmittedJob& job) {
  return job.cluster.empty() ? job.id : job.id + " on cluster " + job.cluster;
}

// The cluster's MaxArraySize, or Slurm's default (with a note) when scontrol does not say.
int max_array_size(const std::string& cluster) {
  const ProgramResult r = run_program(on_cluster({"scontrol", "show", "config"}, cluster));
  const int max = r.status == 0 ? parse_max_array_size(r.out) : -1;
  if (max >= 0) return max;
  std::fprintf(stderr,
               "note: scontrol show config gave no MaxArraySize (%s): assuming Slurm's default, "
               "%d\n",
               trimmed(r.err).c_str(), kSlurmDefaultMaxArraySize);
  return kSlurmDefaultMaxArraySize;
}

std::string clock_text(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  return text;
}

struct Tally {
  int succeeded = 0, failed = 0, running = 0, pending = 0;
  int ended() const { return succeeded + failed; }
};

Tally tally(const std::vector<ElementState>& elements) {
  Tally t;
  for (const ElementState& e : elements) {
    const ElementOutcome outcome = element_outcome(e);
    if (outcome == ElementOutcome::kSucceeded) ++t.succeeded;
    if (outcome == ElementOutcome::kFailed) ++t.failed;
    if (outcome == ElementOutcome::kGoing) (e.state == "PENDING" ? t.pending : t.running) += 1;
  }
  return t;
}

// One progress line on stderr when the counts change (and once a minute while they do not).
class Progress {
 public:
  Progress(std::string job_id, int total) : job_id_(std::move(job_id)), total_(total) {}
  void show(const Tally& t) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const std::string counts = std::to_string(t.ended()) + "/" + std::to_string(total_) +
                               " elements ended (" + std::to_string(t.failed) + " failed), " +
                               std::to_string(t.running) + " running, " +
                               std::to_string(t.pending) + " pending";
    if (counts == last_ && elapsed - last_time_ < 60) return;
    const std::string eta =
        t.ended() > 0 ? clock_text(elapsed * (total_ - t.ended()) / t.ended()) : "?";
    std::fprintf(stderr, "slurm job %s: %s, %s elapsed, ETA %s\n", job_id_.c_str(), counts.c_str(),
                 clock_text(elapsed).c_str(), eta.c_str());
    last_ = counts;
    last_time_ = elapsed;
  }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  std::string job_id_;
  int total_;
  Clock::time_point start_ = Clock::now();
  std::string last_;
  double last_time_ = 0;
};

// Poll squeue until every element has ended (or the controller no longer knows the job). The
// poll interval grows with the run (1 s at first, at most 15 s): a cluster's controller is shared.
void wait_until_ended(const SubmittedJob& job, int shards) {
  const std::string& job_id = job.id;
  Progress progress(job_text(job), shards);
  double failing_since = -1;
  bool seen = false;
  for (;;) {
    const ProgramResult r = run_program(
        on_cluster({"squeue", "-h", "-r", "-t", "all", "-j", job_id, "-o", "%i %T"}, job.cluster));
    if (r.status == 0) {
      failing_since = -1;
      const std::vector<ElementState> elements = parse_squeue_elements(r.out, job_id);
      const Tally t = tally(elements);
      progress.show(t);
      // No element listed: the job has left squeue (or, a minute after submission, never came).
      if (elements.empty() && (seen || progress.elapsed() > 60)) return;
      if (t.ended() == shards && t.running + t.pending == 0) return;
      seen = seen || !elements.empty();
    } else if (r.err.find("Invalid job id") != std::string::npos) {
      return;  // ended longer than MinJobAge ago: sacct has it
    } else if (failing_since < 0) {
      failing_since = progress.elapsed();
    } else if (progress.elapsed() - failing_since > 300) {
      throw std::runtime_error("squeue has failed for 5 minutes while waiting for slurm job " +
                               job_text(job) + ": " + trimmed(r.err));
    }
    const double interval = std::clamp(progress.elapsed() / 20, 1.0, 15.0);
    std::this_thread::sleep_for(std::chrono::duration<double>(interval));
  }
}

// Each element's final state: scontrol while the controller remembers the job, else sacct.
std::map<int, ElementState> final_states(const SubmittedJob& job, int shards) {
  const std::string& job_id = job.id;
  std::map<int, ElementState> by_element;
  const ProgramResult sc =
      run_program(on_cluster({"scontrol", "show", "job", job_id, "-o"}, job.cluster));
  if (sc.status == 0)
    for (const ElementState& e : parse_scontrol_elements(sc.out, job_id)) by_element[e.element] = e;
  if (static_cast<int>(by_element.size()) >= shards) return by_element;
  const ProgramResult sa = run_program(on_cluster(
      {"sacct", "-n", "-P", "-X", "-j", job_id, "-o", "JobID,State,ExitCode"}, job.cluster));
  if (sa.status == 0)
    for (const ElementState& e : parse_sacct_elements(sa.out, job_id))
      by_element.emplace(e.element, e);
  if (static_cast<int>(by_element.size()) < shards)
    throw std::runtime_error("slurm job " + job_text(job) + ": the final state of " +
                             std::to_string(shards - static_cast<int>(by_element.size())) +
                             " element(s) is known neither to scontrol (" + trimmed(sc.err) +
                             ") nor to sacct (" + trimmed(sa.err) + ")");
  return by_element;
}

// Every element that did not succeed, with its state, exit code and the end of its log.
void report_failures(const std::string& job_id, const std::map<int, ElementState>& by_element,
                     const SlurmOptions& o) {
  std::string failures;
  int count = 0;
  for (const auto& [element, e] : by_element) {
    const bool shard_missing = !std::filesystem::exists(slurm_shard_file(o, element));
    if (element_outcome(e) == ElementOutcome::kSucceeded && !shard_missing) continue;
    ++count;
    const std::string err_log = slurm_log_file(o, job_id, element, "err");
    failures += "element " + job_id + "_" + std::to_string(element) + " (shard " +
                std::to_string(element) + "/" + std::to_string(o.shards) + "): " + e.state +
                ", exit code " + (e.exit_code.empty() ? "unknown" : e.exit_code) +
                (shard_missing ? ", no shard file" : "") + "; last lines of " + err_log + ":\n" +
                last_lines(err_log, 10);
  }
  if (count > 0)
    throw std::runtime_error(
        "slurm job " + job_id + ": " + std::to_string(count) + " of " + std::to_string(o.shards) +
        " elements failed (rerun the submission: finished samples are kept)" + ":\n" + failures);
}

// The state word: sacct's "CANCELLED by 1000" is CANCELLED.
std::string state_word(const std::string& state) {
  return state.substr(0, state.find(' '));
}

// JOB_K -> K when the part before '_' is job_id and K is a number; else -1.
int element_of(const std::string& id, const std::string& job_id) {
  if (id.size() <= job_id.size() + 1 || id.compare(0, job_id.size(), job_id) != 0 ||
      id[job_id.size()] != '_')
    return -1;
  const std::string k = id.substr(job_id.size() + 1);
  if (k.size() > 9 || !std::all_of(k.begin(), k.end(), [](char c) { return std::isdigit(c); }))
    return -1;
  return std::stoi(k);
}

// The value of `key=` in one line of `scontrol -o` (fields separated by blanks).
std::string field(const std::string& line, const std::string& key) {
  const std::regex pattern("(^|\\s)" + key + "=(\\S*)");
  std::smatch m;
  return std::regex_search(line, m, pattern) ? m[2].str() : std::string();
}

}  // namespace

std::string slurm_shard_file(const SlurmOptions& o, int shard) {
  return o.work_dir + "/shard-" + std::to_string(shard) + ".jsonl";
}

std::string slurm_log_file(const SlurmOptions& o, const std::string& job_id, int shard,
                           const std::string& extension) {
  return o.work_dir + "/campaign-" + job_id + "_" + std::to_string(shard) + "." + extension;
}

std::string sbatch_script(const std::string& plan_path, const SlurmOptions& o) {
  check_options(o);
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "#SBATCH --job-name=flexloop-campaign\n"
    << "#SBATCH --array=0-" << o.shards - 1;
  if (o.array_throttle > 0) s << "%" << o.array_throttle;
  s << "\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.account.empty()) s << "#SBATCH --account=" << o.account << "\n";
  s << "#SBATCH --time=" << static_cast<long>(std::ceil(o.time_limit_min)) << "\n"
    << "#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --requeue\n"
    << "#SBATCH --open-mode=append\n"
    << "#SBATCH --chdir=\"" << o.work_dir << "\"\n"
    << "#SBATCH --output=\"" << o.work_dir << "/campaign-%A_%a.out\"\n"
    << "#SBATCH --error=\"" << o.work_dir << "/campaign-%A_%a.err\"\n";
  for (const std::string& arg : o.sbatch_args) s << "#SBATCH " << arg << "\n";
  s << "# A requeued element (--requeue) runs its shard again: `campaign run` completes it, and\n"
    << "# --open-mode=append keeps the log of each attempt.\n"
    << "# Written by flexloop campaign submit --engine slurm. Element K of the array runs shard K\n"
    << "# of the plan; `campaign run` is idempotent, so submitting this file again (all of it, or\n"
    << "# one element: sbatch --array=K campaign.sbatch) completes what is missing.\n"
    << "set -eu\n"
    << "shard=\"${SLURM_ARRAY_TASK_ID:?submit this script with sbatch: it is an array job}\"\n"
    << "exec " << shell_quote(o.flexloop_program) << " campaign run " << shell_quote(plan_path)
    << " --shard \"$shard/" << o.shards << "\" -o " << shell_quote(o.work_dir + "/shard-")
    << "\"$shard\"" << shell_quote(".jsonl") << "\n";
  return s.str();
}

ElementOutcome element_outcome(const ElementState& e) {
  static const char* const kGoing[] = {"PENDING",   "RUNNING",   "CONFIGURING", "COMPLETING",
                                       "SUSPENDED", "REQUEUED",  "REQUEUE_FED", "REQUEUE_HOLD",
                                       "RESIZING",  "SIGNALING", "STAGE_OUT",   "STOPPED"};
  for (const char* going : kGoing)
    if (e.state == going) return ElementOutcome::kGoing;
  if (e.state == "COMPLETED" && (e.exit_code.empty() || e.exit_code == "0:0"))
    return ElementOutcome::kSucceeded;
  return ElementOutcome::kFailed;
}

std::vector<ElementState> parse_squeue_elements(const std::string& text,
                                                const std::string& job_id) {
  std::vector<ElementState> elements;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string id, state;
    if (!(words >> id >> state)) continue;
    const int element = element_of(id, job_id);
    if (element >= 0) elements.push_back({element, state_word(state), ""});
  }
  return elements;
}

std::vector<ElementState> parse_scontrol_elements(const std::string& text,
                                                  const std::string& job_id) {
  std::vector<ElementState> elements;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (field(line, "ArrayJobId") != job_id) continue;
    const int element = element_of(job_id + "_" + field(line, "ArrayTaskId"), job_id);
    if (element >= 0)
      elements.push_back({element, state_word(field(line, "JobState")), field(line, "ExitCode")});
  }
  return elements;
}

std::vector<ElementState> parse_sacct_elements(const std::string& text, const std::string& job_id) {
  std::vector<ElementState> elements;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(trimmed(cell));
    if (cells.size() < 3) continue;
    const int element = element_of(cells[0], job_id);
    if (element >= 0) elements.push_back({element, state_word(cells[1]), cells[2]});
  }
  return elements;
}

ShardCount slurm_shard_count(int requested, long evaluations, int max_array_size) {
  if (max_array_size <= 0)
    throw std::runtime_error(
        "this cluster has job arrays disabled (MaxArraySize = 0 in scontrol show config): the "
        "Slurm engine submits an array; run the shards another way (doc/campaign_slurm.md)");
  const std::string limit = "MaxArraySize = " + std::to_string(max_array_size) +
                            " (array indices 0 to " + std::to_string(max_array_size - 1) + ")";
  if (requested > 0) {
    if (requested > max_array_size)
      throw InputError("--shards", std::to_string(requested) + " is more than this cluster's " +
                                       limit + " allows: give at most " +
                                       std::to_string(max_array_size) +
                                       " (each shard then holds more samples: scale --time-limit "
                                       "with it)");
    return {requested, ""};
  }
  const long wanted = std::max(1L, (evaluations + kEvaluationsPerShard - 1) / kEvaluationsPerShard);
  const std::string rule = "one per " + std::to_string(kEvaluationsPerShard) + " of the plan's " +
                           std::to_string(evaluations) + " evaluations";
  if (wanted > max_array_size)
    return {max_array_size, std::to_string(max_array_size) + " shards: the default (" + rule +
                                ", " + std::to_string(wanted) + ") capped at the cluster's " +
                                limit + "; --shards sets the count"};
  return {static_cast<int>(wanted),
          std::to_string(wanted) + " shards: the default (" + rule + "); --shards sets the count"};
}

int parse_max_array_size(const std::string& scontrol_config) {
  static const std::regex pattern(R"(^MaxArraySize\s*=\s*(\d{1,9})\s*$)");
  int smallest = -1;
  std::istringstream in(scontrol_config);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, pattern)) continue;
    const int value = std::stoi(m[1].str());
    smallest = smallest < 0 ? value : std::min(smallest, value);
  }
  return smallest;
}

std::string cluster_of_sbatch_args(const std::vector<std::string>& sbatch_args) {
  std::string cluster;
  for (const std::string& arg : sbatch_args) {
    const std::vector<std::string> words = blank_separated_words(arg);
    for (std::size_t i = 0; i < words.size(); ++i) {
      const std::string& w = words[i];
      const bool next_is_name = (w == "-M" || w == "--clusters" || w == "--cluster");
      if (next_is_name && i + 1 < words.size())
        cluster = words[++i];
      else if (w.rfind("--clusters=", 0) == 0 || w.rfind("--cluster=", 0) == 0)
        cluster = w.substr(w.find('=') + 1);
      else if (w.size() > 2 && w.rfind("-M", 0) == 0)
        cluster = w.substr(2);
    }
  }
  return cluster;
}

SubmittedJob parse_sbatch_parsable(const std::string& out) {
  const std::string text = trimmed(out);
  const std::size_t semicolon = text.find(';');
  SubmittedJob job{text.substr(0, semicolon),
                   semicolon == std::string::npos ? "" : text.substr(semicolon + 1)};
  const auto all_digits = [](const std::string& s) {
    return !s.empty() && s.size() <= 18 &&
           std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(c); });
  };
  const auto is_name = [](const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    });
  };
  if (!all_digits(job.id) || !is_name(job.cluster) ||
      (semicolon != std::string::npos && job.cluster.empty()))
    return {};
  return job;
}

std::vector<std::string> submit_slurm(const std::string& plan_path, const SlurmOptions& options) {
  SlurmOptions o = options;
  namespace fs = std::filesystem;
  if (o.work_dir.empty()) throw InputError("work directory", "not given");
  o.work_dir = fs::absolute(o.work_dir).lexically_normal().string();
  while (o.work_dir.size() > 1 && o.work_dir.back() == '/') o.work_dir.pop_back();
  const std::string plan = fs::absolute(plan_path).lexically_normal().string();
  if (!fs::is_regular_file(plan)) throw InputError(plan_path, "no such plan file");
  for (const std::string& arg : o.sbatch_args) check_sbatch_arg(arg);  // before scontrol
  const ShardCount count = slurm_shard_count(o.shards, o.evaluations,
                                             max_array_size(cluster_of_sbatch_args(o.sbatch_args)));
  o.shards = count.shards;
  if (!count.note.empty()) std::fprintf(stderr, "slurm: %s\n", count.note.c_str());
  const std::string script = sbatch_script(plan, o);
  fs::create_directories(o.work_dir);
  const std::string script_path = o.work_dir + "/campaign.sbatch";
  {
    std::ofstream out(script_path + ".tmp", std::ios::trunc);
    out << script;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + script_path);
  }
  fs::rename(script_path + ".tmp", script_path);

  const SubmittedJob job = submit_script(script_path);
  std::fprintf(stderr, "slurm job %s: %d elements submitted (%s); to cancel it: scancel%s %s\n",
               job_text(job).c_str(), o.shards, script_path.c_str(),
               job.cluster.empty() ? "" : (" -M " + job.cluster).c_str(), job.id.c_str());
  wait_until_ended(job, o.shards);
  report_failures(job.id, final_states(job, o.shards), o);
  std::vector<std::string> shard_files;
  for (int k = 0; k < o.shards; ++k) shard_files.push_back(slurm_shard_file(o, k));
  return shard_files;
}

}  // namespace flexloop::campaign
