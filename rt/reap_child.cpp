// SPDX-License-Identifier: BSD-3-Clause
#include "rt/reap_child.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rt/monotonic_time.hpp"

namespace flexloop::rt {

int reap_child(pid_t child, std::int64_t grace_ns, std::int64_t poll_ns) {
  const std::int64_t end = monotonic_now_ns() + grace_ns;
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) return status;
    if (done < 0) return -1;
    if (monotonic_now_ns() > end) break;
    usleep(static_cast<useconds_t>(poll_ns / 1000));
  }
  kill(child, SIGKILL);
  return waitpid(child, &status, 0) == child ? status : -1;
}

}  // namespace flexloop::rt
