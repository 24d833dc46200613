// SPDX-License-Identifier: BSD-3-Clause
#include "rt/roudi_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/file_lock.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/reap_child.hpp"

namespace flexloop::rt {

namespace {

constexpr const char* kReadyLine = "RouDi is ready for clients";
constexpr const char* kSegmentLine = "in the shared memory [";  // "Reserving N bytes in the ..."
constexpr std::int64_t kPollNs = 2'000'000;

// Everything in `fd` from its start (RouDi's log: small).
std::string read_all(int fd) {
  std::string text;
  char buffer[4096];
  ssize_t n = 0;
  while ((n = pread(fd, buffer, sizeof buffer, static_cast<off_t>(text.size()))) > 0)
    text.append(buffer, static_cast<std::size_t>(n));
  return text;
}

// The last lines of a log, for an error message.
std::string tail(const std::string& text) {
  const std::size_t from = text.size() > 600 ? text.rfind('\n', text.size() - 600) : 0;
  return text.substr(from == std::string::npos ? 0 : from);
}

std::string status_text(int status) {
  if (status < 0) return "ended (reaped elsewhere)";
  if (WIFSIGNALED(status))
    return "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
           strsignal(WTERMSIG(status)) + ")";
  return "exited with status " + std::to_string(WEXITSTATUS(status));
}

// The names after "in the shared memory [" in RouDi's log: the segments it created.
std::vector<std::string> logged_segments(const std::string& log) {
  std::vector<std::string> names;
  for (std::size_t at = log.find(kSegmentLine); at != std::string::npos;
       at = log.find(kSegmentLine, at + 1)) {
    const std::size_t from = at + std::strlen(kSegmentLine);
    const std::size_t to = log.find(']', from);
    if (to != std::string::npos) names.push_back(log.substr(from, to - from));
  }
  return names;
}

std::string make_folder() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/flexloop-roudi-XXXXXX";
  if (!mkdtemp(pattern.data()))
    throw RoudiError("iox-roudi: cannot create a folder for its config (" + pattern +
                     "): " + std::strerror(errno));
  return pattern;
}

// The child between fork and exec: own process group, ends with its parent, output to the log.
[[noreturn]] void exec_roudi(const std::string& exe, const std::string& config,
                             const char* monitoring, const std::string& log, pid_t parent,
                             int error_fd) {
  setpgid(0, 0);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(127);
  const int out = open(log.c_str(), O_WRONLY | O_CLOEXEC);
  const int in = open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out >= 0 && in >= 0) {
    dup2(in, 0);
    dup2(out, 1);
    dup2(out, 2);
    const char* argv[] = {exe.c_str(), "-c", config.c_str(), "-m", monitoring, nullptr};
    execvp(exe.c_str(), const_cast<char* const*>(argv));
  }
  const int e = errno;
  (void)!write(error_fd, &e, sizeof e);
  _exit(127);
}

}  // namespace

std::vector<RoudiMempool> mempools_for_messages(std::size_t largest_message_bytes,
                                                std::uint32_t count) {
  const std::size_t line = 64;
  const std::size_t bytes =
      std::max<std::size_t>(line, (largest_message_bytes + line - 1) / line * line);
  return {{static_cast<std::uint32_t>(bytes), count}};
}

std::string roudi_config_toml(const std::vector<RoudiMempool>& mempools) {
  if (mempools.empty()) throw std::invalid_argument("RouDi config: no mempool");
  std::string toml =
      "# iceoryx 2.0 RouDi config, written by flexloop\n"
      "[general]\nversion = 1\n\n[[segment]]\n";
  for (const RoudiMempool& m : mempools) {
    if (m.count == 0 || m.chunk_bytes == 0 || m.chunk_bytes % 8 != 0)
      throw std::invalid_argument(
          "RouDi config: a mempool needs a chunk size that is a positive "
          "multiple of 8 and a positive count");
    toml += "\n[[segment.mempool]]\nsize = " + std::to_string(m.chunk_bytes) +
            "\ncount = " + std::to_string(m.count) + "\n";
  }
  return toml;
}

std::optional<pid_t> running_roudi_pid() {
  return common::flock_holder(kRoudiLockFile);
}

RoudiProcess::RoudiProcess(const RoudiOptions& options) : stop_grace_ns_(options.stop_grace_ns) {
  if (const auto other = running_roudi_pid())
    throw RoudiError("iox-roudi already runs on this host (pid " + std::to_string(*other) +
                     " holds " + kRoudiLockFile +
                     "): iceoryx 2.0 has one RouDi per host, so a second iceoryx run cannot "
                     "start its own; end the other run first, or use --transport lcm");
  const std::string toml = roudi_config_toml(options.mempools);  // before anything is made
  folder_ = make_folder();
  config_path_ = folder_ + "/roudi.toml";
  log_path_ = folder_ + "/roudi.log";
  std::ofstream(config_path_) << toml;
  log_fd_ = open(log_path_.c_str(), O_RDONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (log_fd_ < 0) fail("cannot create its log " + log_path_ + ": " + std::strerror(errno));
  start(options);
  wait_until_ready(options.ready_timeout_ns);
  remove_folder();  // RouDi has read its config; its log is read through log_fd_
}

std::string RoudiProcess::log() const {
  return log_fd_ >= 0 ? read_all(log_fd_) : std::string();
}

void RoudiProcess::remove_folder() {
  std::error_code ignored;
  if (!folder_.empty()) std::filesystem::remove_all(folder_, ignored);
  folder_.clear();
}

RoudiProcess::~RoudiProcess() {
  stop();
  remove_folder();
  if (log_fd_ >= 0) close(log_fd_);
}

void RoudiProcess::start(const RoudiOptions& options) {
  int error_pipe[2];
  if (pipe2(error_pipe, O_CLOEXEC) != 0) fail("cannot create a pipe");
  const pid_t parent = getpid();
  std::fflush(nullptr);
  pid_ = fork();
  if (pid_ < 0) fail("fork failed");
  if (pid_ == 0)
    exec_roudi(options.executable, config_path_, options.monitoring ? "on" : "off", log_path_,
               parent, error_pipe[1]);
  close(error_pipe[1]);
  int exec_errno = 0;
  const bool exec_failed = read(error_pipe[0], &exec_errno, sizeof exec_errno) ==
                           static_cast<ssize_t>(sizeof exec_errno);
  close(error_pipe[0]);
  if (exec_failed)
    fail("cannot run '" + options.executable + "': " + std::strerror(exec_errno) +
         " (Debian's package iceoryx installs iox-roudi)");
}

void RoudiProcess::wait_until_ready(std::int64_t timeout_ns) {
  const std::int64_t give_up = monotonic_now_ns() + timeout_ns;
  while (log().find(kReadyLine) == std::string::npos) {
    if (!alive()) fail("it " + status_text(*exit_status_) + " before it was ready");
    if (monotonic_now_ns() > give_up)
      fail("it was not ready for clients within " + std::to_string(timeout_ns / 1'000'000) + " ms");
    usleep(kPollNs / 1000);
  }
}

void RoudiProcess::fail(const std::string& why) {
  std::string message = "iox-roudi";
  if (pid_ > 0) message += " (pid " + std::to_string(pid_) + ")";
  message += ": " + why;
  if (const std::string said = pid_ > 0 ? tail(log()) : ""; !said.empty())
    message += "; its log ends:\n" + said;
  stop();
  remove_folder();
  if (log_fd_ >= 0) close(log_fd_);
  log_fd_ = -1;
  throw RoudiError(message);
}

bool RoudiProcess::alive() {
  if (pid_ <= 0 || exit_status_) return false;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) != pid_) return true;
  exit_status_ = status;
  return false;
}

std::string RoudiProcess::describe() {
  const std::string who = "iox-roudi (pid " + std::to_string(pid_) + ") ";
  if (alive()) return who + "runs";
  return exit_status_ ? who + status_text(*exit_status_) : who + "was never started";
}

void RoudiProcess::stop() {
  if (pid_ <= 0 || stopped_) return;
  if (alive()) {
    kill(pid_, SIGTERM);
    exit_status_ = reap_child(pid_, stop_grace_ns_, kPollNs);
  }
  remove_leftovers();
  stopped_ = true;
}

void RoudiProcess::remove_leftovers() {
  // Only when no RouDi runs now: the names are global, and a later RouDi's are not ours.
  if (running_roudi_pid()) return;
  for (const std::string& name : logged_segments(log())) shm_unlink(("/" + name).c_str());
  shm_unlink((std::string("/") + kRoudiManagementSegment).c_str());
  for (const char* path : {kRoudiSocket, kRoudiSocketLock, kRoudiLockFile}) unlink(path);
}

}  // namespace flexloop::rt
