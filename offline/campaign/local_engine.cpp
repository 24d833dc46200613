// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/local_engine.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <thread>

#include "offline/campaign/shard_run.hpp"

extern char** environ;

namespace flexloop::campaign {

namespace {

pid_t start_shard(const LocalEngineOptions& o, int k, const std::string& file) {
  std::vector<std::string> args = {
      o.program,   "campaign", "run",
      o.plan_path, "--shard",  std::to_string(k) + "/" + std::to_string(o.shards),
      "-o",        file,       "--quiet"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int e = posix_spawn(&pid, o.program.c_str(), nullptr, nullptr, argv.data(), environ))
    throw std::runtime_error("cannot start " + o.program + ": " + std::strerror(e));
  return pid;
}

std::string duration_text(double s) {
  char buf[32];
  if (s < 90)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 5400)
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  else
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  return buf;
}

}  // namespace

std::string progress_text(long done, long total, double elapsed_s, long done_before) {
  constexpr int kWidth = 30;
  const double share = total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
  const int filled = static_cast<int>(share * kWidth);
  std::string bar = "[" + std::string(filled, '#') + std::string(kWidth - filled, '.') + "]";
  char buf[160];
  const double rate = elapsed_s > 0 ? static_cast<double>(done - done_before) / elapsed_s : 0;
  std::snprintf(buf, sizeof buf, " %3.0f %% %ld/%ld  %.1f/s", 100 * share, done, total, rate);
  std::string text = bar + buf;
  if (rate > 0 && done < total)
    text += "  ~" + duration_text(static_cast<double>(total - done) / rate) + " left";
  return text;
}

std::vector<std::string> run_local(const LocalEngineOptions& o) {
  std::filesystem::create_directories(o.work_dir);
  std::vector<std::string> files;
  for (int k = 0; k < o.shards; ++k)
    files.push_back(
        (std::filesystem::path(o.work_dir) / ("shard-" + std::to_string(k) + ".jsonl")).string());
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const auto start = std::chrono::steady_clock::now();
  auto last = start;
  long at_start = 0;
  for (const auto& f : files) at_start += complete_lines(f);
  GrowingLineCount counter;      // each tick reads only what the shards appended since the last
  std::map<pid_t, int> running;  // child -> shard
  std::vector<std::string> failures;
  int next = 0;
  while (next < o.shards || !running.empty()) {
    while (next < o.shards && static_cast<int>(running.size()) < o.jobs) {
      running[start_shard(o, next, files[next])] = next;
      ++next;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid > 0 && running.count(pid)) {
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        failures.push_back(
            "shard " + std::to_string(running[pid]) + "/" + std::to_string(o.shards) +
            (WIFEXITED(status) ? " exited " + std::to_string(WEXITSTATUS(status))
                               : " was killed by signal " + std::to_string(WTERMSIG(status))));
      running.erase(pid);
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto now = std::chrono::steady_clock::now();
    if (o.quiet || now - last < std::chrono::milliseconds(tty ? 250 : 10000)) continue;
    last = now;
    long done = 0;
    for (const auto& f : files) done += counter.lines(f);
    const double s = std::chrono::duration<double>(now - start).count();
    const std::string text = progress_text(done, o.evaluations, s, at_start);
    std::fprintf(stderr, "%s%s%s", tty ? "\r\033[K" : "", text.c_str(), tty ? "" : "\n");
  }
  if (!o.quiet) {
    long done = 0;
    for (const auto& f : files) done += complete_lines(f);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "%s%s\n", tty ? "\r\033[K" : "",
                 progress_text(done, o.evaluations, s, at_start).c_str());
  }
  if (!failures.empty()) {
    std::string what = "the local engine's shards failed:";
    for (const auto& f : failures) what += "\n  " + f;
    throw std::runtime_error(what);
  }
  return files;
}

}  // namespace flexloop::campaign
