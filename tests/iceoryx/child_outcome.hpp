// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Runs a piece of a test in a child process (an iceoryx runtime is one per process, and the
// process that owns RouDi must not register) and returns the int it computed. The number comes
// back over a pipe, not as the exit status: the child leaves with exit(), so that iceoryx's
// runtime deregisters in its static destructor, and what runs then (a sanitizer's leak check)
// must not change the outcome. -1: the child ended without saying (killed after `grace_ns`).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "rt/reap_child.hpp"

namespace flexloop::test {

template <class Body>
int outcome_in_child(Body&& body, std::int64_t grace_ns) {
  int fd[2];
  if (pipe(fd) != 0) return -1;
  std::fflush(nullptr);  // nothing buffered may be written twice
  const pid_t child = fork();
  if (child == 0) {
    close(fd[0]);
    const int outcome = body();
    (void)!write(fd[1], &outcome, sizeof outcome);
    close(fd[1]);
    std::exit(0);
  }
  close(fd[1]);
  int outcome = -1;
  if (read(fd[0], &outcome, sizeof outcome) != static_cast<ssize_t>(sizeof outcome)) outcome = -1;
  close(fd[0]);
  rt::reap_child(child, grace_ns);
  return outcome;
}

}  // namespace flexloop::test
