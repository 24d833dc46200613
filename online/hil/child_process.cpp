// SPDX-License-Identifier: BSD-3-Clause
#include "online/hil/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "rt/monotonic_time.hpp"

namespace flexloop::hil {

namespace {

void write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

ChildProcess::ChildProcess(const Body& body, ChildEnd end) {
  int fds[2], resume[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe");
  if (pipe2(resume, O_CLOEXEC) != 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error("cannot create a pipe");
  }
  std::fflush(nullptr);
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ < 0) {
    for (const int fd : {fds[0], fds[1], resume[0], resume[1]}) close(fd);
    throw std::runtime_error("fork failed");
  }
  if (pid_ == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(1);  // the parent died before the line above
    close(fds[0]);
    close(resume[1]);
    const ChildLink link{.ready = [fd = fds[1]] { write_all(fd, "R"); },
                         .pause =
                             [fd = fds[1], in = resume[0]] {
                               write_all(fd, "P");
                               char go = 0;
                               while (read(in, &go, 1) < 0 && errno == EINTR) {
                               }
                             }};
    std::string out;
    int code = 0;
    try {
      // Appended, not "O" + body(...): GCC 12 warns falsely (-Wrestrict) on that prepend.
      out = std::string("O").append(body(link));
    } catch (const std::exception& e) {
      out = std::string("E") + e.what();
      code = 1;
    }
    std::fflush(nullptr);
    write_all(fds[1], out);
    if (end == ChildEnd::kExit) std::exit(code);
    _exit(code);
  }
  close(fds[1]);
  close(resume[0]);
  fd_ = fds[0];
  resume_fd_ = resume[1];
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0) reap(true);
  if (fd_ >= 0) close(fd_);
  if (resume_fd_ >= 0) close(resume_fd_);
}

bool ChildProcess::read_until_eof(std::int64_t deadline_ns) {
  char chunk[4096];
  for (;;) {
    const std::int64_t left = deadline_ns - rt::monotonic_now_ns();
    if (left <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(left / 1'000'000 + 1));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return false;
    const ssize_t n = read(fd_, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    buffer_.append(chunk, static_cast<std::size_t>(n));
    if (buffer_[0] == 'R' || buffer_[0] == 'P') return false;  // a signal first: caller decides
  }
}

void ChildProcess::wait_ready(std::int64_t timeout_ns) {
  const std::int64_t deadline = rt::monotonic_now_ns() + timeout_ns;
  while (buffer_.empty() && rt::monotonic_now_ns() < deadline) read_until_eof(deadline);
  if (!buffer_.empty() && buffer_[0] == 'R') {
    buffer_.erase(0, 1);
    return;
  }
  if (!buffer_.empty() && buffer_[0] == 'E') throw std::runtime_error(buffer_.substr(1));
  throw std::runtime_error("child process " + std::to_string(pid_) + " was not ready in time");
}

void ChildProcess::signal(int sig) {
  if (pid_ > 0) kill(pid_, sig);
}

std::string ChildProcess::finish(std::int64_t timeout_ns, const std::function<void()>& tick,
                                 const std::function<void()>& on_pause) {
  std::int64_t deadline = rt::monotonic_now_ns() + timeout_ns;
  constexpr std::int64_t kTickNs = 250'000'000;
  bool eof = false;
  while (!eof && rt::monotonic_now_ns() < deadline) {
    eof = read_until_eof(tick ? std::min(deadline, rt::monotonic_now_ns() + kTickNs) : deadline);
    while (!buffer_.empty() && (buffer_[0] == 'R' || buffer_[0] == 'P')) {
      const bool paused = buffer_[0] == 'P';
      buffer_.erase(0, 1);  // 'R': a late "ready"
      if (!paused) continue;
      const std::int64_t paused_at = rt::monotonic_now_ns();
      if (on_pause) on_pause();
      deadline += rt::monotonic_now_ns() - paused_at;
      write_all(resume_fd_, "G");
    }
    if (tick && !eof) tick();
  }
  reap(!eof);
  if (!eof) throw std::runtime_error("child process did not finish in time (killed)");
  if (buffer_.empty())
    throw std::runtime_error(killed_by_.empty()
                                 ? "child process ended without a result"
                                 : "child process killed by " + killed_by_ + " without a result");
  if (buffer_[0] == 'E') throw std::runtime_error(buffer_.substr(1));
  return buffer_.substr(1);
}

void ChildProcess::reap(bool kill_first) {
  if (kill_first) kill(pid_, SIGKILL);
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  // Not when this process killed it: the SIGKILL is ours, not the child's end.
  if (!kill_first && WIFSIGNALED(status)) {
    const char* abbrev = sigabbrev_np(WTERMSIG(status));
    killed_by_ =
        abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(WTERMSIG(status));
  }
  pid_ = -1;
}

}  // namespace flexloop::hil
