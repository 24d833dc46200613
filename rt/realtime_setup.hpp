// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small single-purpose helpers that make a thread fit for a hard-rate loop: CPU affinity,
// memory locking with a prefaulted stack, SCHED_FIFO priority when permitted, denormals flushed
// to zero, and holding /dev/cpu_dma_latency at 0 (as cyclictest does). They run before the loop,
// may allocate, and never throw for a refused privilege: each returns a SetupStatus whose message
// says what was done or why not, so a process can carry on without real-time rights and say so.
//
// Start-up order (doc/design.md §11): non-real-time set-up (open files, LCM, allocate buffers),
// then pin, mlockall, prefault the stack, and only then raise the priority --
// apply_realtime_setup() does exactly that for the calling thread. Threads inherit affinity and
// scheduling policy at creation, so threads created after it (e.g. LCM's receive thread) run at the
// same priority on the same CPU; threads created before it keep their own (use the *_thread
// variants by id).
//
// Caveat: a SCHED_FIFO thread that never sleeps is throttled by the kernel's RT bandwidth limit
// (/proc/sys/kernel/sched_rt_runtime_us, 950000 of every 1000000 us by default): it loses the
// CPU for the rest of each second once it used 95 % of it. Prefer sleep-then-spin (WaitMode::
// kHybrid in rt/periodic_clock.hpp) to pure spinning at real-time priority.
#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace flexloop::rt {

/// Outcome of one set-up step: ok, and a human-readable message either way.
struct SetupStatus {
  bool ok = false;
  std::string message;
};

/// Restricts the calling thread to one CPU (0-based).
SetupStatus pin_current_thread_to_cpu(int cpu);
/// Restricts thread `tid` (a kernel thread id, see process_thread_ids()) to one CPU.
SetupStatus pin_thread_to_cpu(pid_t tid, int cpu);

/// mlockall(MCL_CURRENT | MCL_FUTURE), keeps freed heap memory in the process (no trimming, no
/// mmap for large blocks, so a later allocation cannot fault), then touches `stack_bytes` of the
/// calling thread's stack so that its pages are resident before the loop starts.
/// stack_bytes must stay well below the thread's stack size (8 MiB by default).
SetupStatus lock_memory_and_prefault_stack(std::size_t stack_bytes);

/// SCHED_FIFO at `priority` (1..99) for the calling thread. When not permitted (EPERM: not root,
/// no CAP_SYS_NICE, RLIMIT_RTPRIO too low) the thread stays at its normal policy and the message
/// says so and why.
SetupStatus try_set_fifo_priority(int priority);
/// The same for thread `tid`.
SetupStatus try_set_thread_fifo_priority(pid_t tid, int priority);

/// Timer slack of 1 ns for the calling thread: sleeps of a SCHED_OTHER thread otherwise end up
/// to 50 us late. (SCHED_FIFO threads get no slack anyway.)
SetupStatus set_minimal_timer_slack();

/// Kernel thread ids of every thread of this process (/proc/self/task), sorted.
std::vector<pid_t> process_thread_ids();

/// While alive, holds /dev/cpu_dma_latency open with the value 0, which keeps every CPU out of
/// deep idle states (so a sleeping loop wakes up quickly). When the device cannot be opened or
/// written (no root, no device) active() is false and message() says why; nothing else changes.
class CpuDmaLatencyHold {
 public:
  CpuDmaLatencyHold();
  ~CpuDmaLatencyHold();
  CpuDmaLatencyHold(const CpuDmaLatencyHold&) = delete;
  CpuDmaLatencyHold& operator=(const CpuDmaLatencyHold&) = delete;

  bool active() const { return fd_ >= 0; }
  const std::string& message() const { return message_; }

 private:
  int fd_ = -1;
  std::string message_;
};

/// What apply_realtime_setup() should do. cpu < 0: leave affinity alone; fifo_priority 0: stay
/// SCHED_OTHER (and take 1 ns timer slack); lock_memory false: skip mlockall and prefault.
struct RealtimeOptions {
  int cpu = -1;
  bool lock_memory = true;
  std::size_t prefault_stack_bytes = 512 * 1024;
  int fifo_priority = 0;
};

/// The outcome of each step of apply_realtime_setup().
struct RealtimeReport {
  SetupStatus affinity;
  SetupStatus memory;
  SetupStatus priority;
  SetupStatus denormals;  ///< always applied: rt/denormals.hpp
  /// True when SCHED_FIFO was asked for and granted.
  bool fifo = false;
  /// One line per step, e.g. for a process's start-up banner.
  std::string describe() const;
};

/// Pin, lock and prefault, then raise the priority, for the calling thread, in that order; and
/// flush denormals to zero (rt/denormals.hpp).
RealtimeReport apply_realtime_setup(const RealtimeOptions& options);

}  // namespace flexloop::rt
