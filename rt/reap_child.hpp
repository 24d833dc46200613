// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Ending a child process this process forked: wait for it, and kill it by its pid (never by name)
// when it does not end in time. Used by the baselines' forks and by the RouDi component.
#include <sys/types.h>

#include <cstdint>

namespace flexloop::rt {

/// Waits up to `grace_ns` for `child` to end (polling every `poll_ns`), then SIGKILLs it and
/// waits for it. Returns the wait status (as waitpid's), or -1 when `child` is not ours.
int reap_child(pid_t child, std::int64_t grace_ns, std::int64_t poll_ns = 1'000'000);

}  // namespace flexloop::rt
