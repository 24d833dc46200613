// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One forked helper process of `flexloop hil` (the plant, the controller): the child runs a
// function and hands its result text back over a pipe; it can say "ready" before that (e.g. once
// subscribed). Orchestration only: allocates, throws std::runtime_error.
//
// Pipe protocol, child to parent: 'R' once when ready, 'P' each time it pauses, then 'O' + text
// when the body returned, or 'E' + message when it threw; then EOF. A paused child waits for one
// byte on a second pipe, parent to child, which the parent writes once its on_pause returned
// (e.g. a baseline segment measured while the loop stands still). The child ends with _exit (the
// parent's atexit handlers and stdio buffers are not its to run; stdout is flushed before fork and
// by the child before _exit) -- or, asked for (ChildEnd::kExit), with exit(): a child registered
// with iceoryx's RouDi deregisters only in the runtime's static destructor. A child whose parent
// dies gets SIGTERM (PR_SET_PDEATHSIG): no loop is left spinning behind.
#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <string>

namespace flexloop::hil {

/// What the child's body can tell its parent before its result.
struct ChildLink {
  std::function<void()> ready;  ///< once (e.g. subscribed): wait_ready() returns
  std::function<void()> pause;  ///< blocks until the parent's on_pause returned
};

/// How the child leaves once its result is written.
enum class ChildEnd { kImmediate, kExit };

class ChildProcess {
 public:
  using Body = std::function<std::string(const ChildLink& link)>;

  /// Forks and runs body in the child.
  explicit ChildProcess(const Body& body, ChildEnd end = ChildEnd::kImmediate);
  ~ChildProcess();  // kills (SIGKILL) and reaps a child still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Waits up to timeout_ns for "ready"; std::runtime_error with the child's error (or a
  /// timeout) otherwise.
  void wait_ready(std::int64_t timeout_ns);
  /// Sends a signal to the child (by its pid).
  void signal(int sig);
  /// Waits up to timeout_ns (not counting pauses) for the child's result and reaps it (SIGKILL
  /// after the timeout); std::runtime_error carrying the child's error when it failed, or saying
  /// how it ended (killed_by()) when it gave no result. tick, when
  /// given, is called about four times a second while waiting (a status line, forwarding a stop
  /// request); on_pause each time the child paused, which resumes when it returns.
  std::string finish(std::int64_t timeout_ns, const std::function<void()>& tick = {},
                     const std::function<void()>& on_pause = {});

  pid_t pid() const { return pid_; }
  /// The signal that ended the child ("SIGSEGV"), once reaped; empty when it exited (or runs).
  const std::string& killed_by() const { return killed_by_; }

 private:
  // Reads into buffer_ until EOF, the deadline or a 'R'/'P' at its start; true at EOF.
  bool read_until_eof(std::int64_t deadline_ns);
  void reap(bool kill_first);

  pid_t pid_ = -1;
  int fd_ = -1;         // from the child
  int resume_fd_ = -1;  // to the child: one byte per resume
  std::string buffer_;
  std::string killed_by_;
};

}  // namespace flexloop::hil
