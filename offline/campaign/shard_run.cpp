// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/shard_run.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string_view>

#include "common/input_error.hpp"

namespace flexloop::campaign {

Shard parse_shard(const std::string& text) {
  Shard s;
  char slash = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%ld%c%ld%c", &s.k, &slash, &s.m, &rest) != 3 || slash != '/' ||
      s.m < 1 || s.k < 0 || s.k >= s.m)
    throw common::InputError("--shard", "'" + text + "' is not K/M with 0 <= K < M");
  return s;
}

std::vector<long> shard_indices(const Shard& shard, long evaluations) {
  std::vector<long> out;
  for (long i = shard.k; i < evaluations; i += shard.m) out.push_back(i);
  return out;
}

nlohmann::json plan_line(const std::string& text, const std::string& place,
                         const std::string& plan_id) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error&) {
    throw common::InputError(place, "not a JSON line: the shard file is damaged");
  }
  if (!j.is_object() || j.value("plan_id", std::string()) != plan_id)
    throw common::InputError(
        place, "this line belongs to another plan (plan_id " +
                   (j.is_object() ? j.value("plan_id", std::string("none")) : std::string("none")) +
                   "; this plan's is " + plan_id + ")");
  return j;
}

std::unique_ptr<common::ExclusiveFileLock> lock_shard(const std::string& file) {
  std::unique_ptr<common::ExclusiveFileLock> lock;
  try {
    lock = common::ExclusiveFileLock::try_take(file);
  } catch (const std::runtime_error& e) {
    throw common::InputError(file, "cannot be opened to write the shard");
  }
  if (lock) return lock;
  const auto holder = common::flock_holder(file);
  throw common::InputError(
      file,
      "another run is writing this shard (" +
          (holder ? "pid " + std::to_string(*holder) : std::string("a process on another host")) +
          " holds its lock): wait for it to end or stop it; two writers would interleave "
          "their lines");
}

namespace {

// A line that is no JSON object at all: torn, or the zeros a crash leaves in a file's tail.
bool damaged(std::string_view line) {
  if (line.find('\0') != std::string_view::npos) return true;
  try {
    return !nlohmann::json::parse(line).is_object();
  } catch (const nlohmann::json::parse_error&) {
    return true;
  }
}

// True when every complete line from `start` on is damaged: the file's tail, not its middle.
bool damaged_to_the_end(const std::string& text, std::size_t start) {
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    if (!damaged(std::string_view(text).substr(start, end - start))) return false;
  return true;
}

}  // namespace

std::vector<long> completed_indices(const std::string& file, const std::string& plan_id,
                                    const Shard& shard, long evaluations, std::string* repaired) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::vector<long> done;
  std::set<long> seen;
  std::size_t start = 0;
  long line_number = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string place = file + ":" + std::to_string(++line_number);
    const std::string line = text.substr(start, end - start);
    if (damaged(line) && damaged_to_the_end(text, start)) break;  // cut below
    const nlohmann::json j = plan_line(line, place, plan_id);
    const long index = j.value("index", -1L);
    if (index < 0 || index >= evaluations || index % shard.m != shard.k)
      throw common::InputError(place, "index " + std::to_string(index) + " is not one of shard " +
                                          std::to_string(shard.k) + "/" + std::to_string(shard.m));
    if (!seen.insert(index).second)
      throw common::InputError(place, "index " + std::to_string(index) + " is there twice");
    done.push_back(index);
  }
  // A damaged tail (a torn last line, zeros) was being written when a run died: cut it off.
  if (start < text.size()) {
    std::filesystem::resize_file(file, start);
    if (repaired)
      *repaired = file + ": cut " + std::to_string(text.size() - start) +
                  " bytes of a damaged tail after line " + std::to_string(done.size()) +
                  " (a run died while writing); its samples are computed again";
  }
  return done;
}

namespace {

// FILE.attempt: the index being computed and how many runs have started it. Removed by SIGINT,
// SIGTERM and SIGHUP on their way out (a user's Ctrl-C, a scheduler's cancel or preemption is not
// the sample's fault); left by a crash or SIGKILL. One death at a sample may be the machine's (a
// node lost, a kill -9): the sample is computed again. Two at the same sample are the sample's: the
// next run writes it as crashed.
char g_attempt_file[4096];

extern "C" void forget_attempt_and_die(int signal_number) {
  ::unlink(g_attempt_file);
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

class AttemptMarker {
 public:
  explicit AttemptMarker(const std::string& shard_file) : path_(shard_file + ".attempt") {
    if (path_.size() >= sizeof g_attempt_file)
      throw common::InputError(shard_file, "the path is too long");
    std::memcpy(g_attempt_file, path_.c_str(), path_.size() + 1);
    struct sigaction action {};
    action.sa_handler = forget_attempt_and_die;
    sigemptyset(&action.sa_mask);
    for (std::size_t k = 0; k < std::size(kSignals); ++k)
      ::sigaction(kSignals[k], &action, &previous_[k]);
  }
  ~AttemptMarker() {
    for (std::size_t k = 0; k < std::size(kSignals); ++k)
      ::sigaction(kSignals[k], &previous_[k], nullptr);
  }
  AttemptMarker(const AttemptMarker&) = delete;
  AttemptMarker& operator=(const AttemptMarker&) = delete;

  struct Attempt {
    long index = -1, runs = 0;  // runs that started `index` and died in it
  };
  /// The sample the last run was computing when it died ({-1, 0}: none).
  Attempt last() const {
    std::ifstream in(path_);
    Attempt a;
    return in >> a.index >> a.runs ? a : Attempt{};
  }
  void start(long index, long runs) const {
    std::FILE* f = std::fopen(path_.c_str(), "w");
    if (!f || std::fprintf(f, "%ld %ld\n", index, runs) < 0 || std::fclose(f) != 0)
      throw std::runtime_error("cannot write " + path_);
  }
  void finish() const noexcept {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }

 private:
  static constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
  std::string path_;
  struct sigaction previous_[std::size(kSignals)]{};
};

// Appends one line in one write, flushed: a kill leaves at most this line torn.
void append_line(std::FILE* out, const nlohmann::json& line, const std::string& file) {
  const std::string text = line.dump() + "\n";
  if (std::fwrite(text.data(), 1, text.size(), out) != text.size() || std::fflush(out) != 0)
    throw std::runtime_error("cannot write " + file);
}

}  // namespace

ShardRunResult run_shard(const std::string& file, const std::string& plan_id, const Shard& shard,
                         long evaluations, const std::function<nlohmann::json(long)>& line_of,
                         const FailedLine& failed_line,
                         const std::function<void(long, long)>& progress) {
  const std::vector<long> all = shard_indices(shard, evaluations);
  const std::vector<long> done_list = completed_indices(file, plan_id, shard, evaluations);
  const std::set<long> done(done_list.begin(), done_list.end());
  ShardRunResult r;
  r.already = static_cast<long>(done.size());
  const long total = static_cast<long>(all.size());
  if (progress) progress(r.already, total);
  const AttemptMarker attempt(file);
  const AttemptMarker::Attempt died = attempt.last();
  std::FILE* out = std::fopen(file.c_str(), "ab");
  if (!out) throw common::InputError(file, "cannot be written");
  try {
    for (long index : all) {
      if (done.count(index)) continue;
      if (index == died.index && died.runs >= 2) {
        const std::string status =
            "error: crashed: two runs died while computing this sample (a signal such as "
            "SIGSEGV, or the OOM killer)";
        append_line(
            out,
            failed_line
                ? failed_line(index, status)
                : nlohmann::json{{"plan_id", plan_id}, {"index", index}, {"status", status}},
            file);
        ++r.crashed;
      } else {
        attempt.start(index, index == died.index ? died.runs + 1 : 1);
        append_line(out, line_of(index), file);
        ++r.computed;
      }
      if (progress) progress(r.already + r.computed + r.crashed, total);
    }
  } catch (...) {
    std::fclose(out);
    attempt.finish();  // an error this process reports (a full disk) is not the sample's crash
    throw;
  }
  if (std::fclose(out) != 0) throw std::runtime_error("cannot write " + file);
  attempt.finish();
  return r;
}

long complete_lines(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return 0;
  return static_cast<long>(
      std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n'));
}

long GrowingLineCount::lines(const std::string& file) {
  Seen& seen = seen_[file];
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(file, error);
  if (error) return seen = Seen{}, 0;  // not there (yet)
  if (size < seen.bytes) seen = Seen{};
  std::ifstream in(file, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(seen.bytes));
  char buffer[1 << 16];
  while (in && seen.bytes < size) {
    in.read(buffer, static_cast<std::streamsize>(
                        std::min<std::uintmax_t>(sizeof buffer, size - seen.bytes)));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    seen.lines += std::count(buffer, buffer + got, '\n');
    seen.bytes += static_cast<std::uintmax_t>(got);
  }
  return seen.lines;
}

}  // namespace flexloop::campaign
