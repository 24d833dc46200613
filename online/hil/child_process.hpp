#pragma once
// One forked helper process of `flexloop hil` (the plant, the controller): the child runs a
// function and hands its result text back over a pipe; it can say "ready" before that (e.g. once
// subscribed). Orchestration only: allocates, throws std::runtime_error.
//
// Pipe protocol: 'R' once when ready, then 'O' + text when the body returned, or 'E' + message
// when it threw; then EOF. The child ends with _exit (the parent's atexit handlers and stdio
// buffers are not its to run; stdout is flushed before fork and by the child before _exit). A
// child whose parent dies gets SIGTERM (PR_SET_PDEATHSIG): no loop is left spinning behind.
#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <string>

namespace flexloop::hil {

class ChildProcess {
 public:
  using Body = std::function<std::string(const std::function<void()>& ready)>;

  /// Forks and runs body in the child.
  explicit ChildProcess(const Body& body);
  ~ChildProcess();  // kills (SIGKILL) and reaps a child still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Waits up to timeout_ns for "ready"; std::runtime_error with the child's error (or a
  /// timeout) otherwise.
  void wait_ready(std::int64_t timeout_ns);
  /// Sends a signal to the child (by its pid).
  void signal(int sig);
  /// Waits up to timeout_ns for the child's result and reaps it (SIGKILL after the timeout);
  /// std::runtime_error carrying the child's error when it failed. tick, when given, is called
  /// about four times a second while waiting (a status line, forwarding a stop request).
  std::string finish(std::int64_t timeout_ns, const std::function<void()>& tick = {});

  pid_t pid() const { return pid_; }

 private:
  // Reads into buffer_ until EOF or the deadline; true at EOF.
  bool read_until_eof(std::int64_t deadline_ns);
  void reap(bool kill_first);

  pid_t pid_ = -1;
  int fd_ = -1;
  std::string buffer_;
};

}  // namespace flexloop::hil
