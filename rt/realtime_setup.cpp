// SPDX-License-Identifier: BSD-3-Clause
#include "rt/realtime_setup.hpp"

#include "rt/denormals.hpp"

#include <alloca.h>
#include <dirent.h>
#include <fcntl.h>
#include <malloc.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace flexloop::rt {

namespace {

std::string errno_text(int err) {
  return std::string(std::strerror(err));
}

SetupStatus ok(std::string message) {
  return {true, std::move(message)};
}
SetupStatus failed(std::string message) {
  return {false, std::move(message)};
}

std::string thread_name(pid_t tid) {
  return tid == 0 ? std::string("this thread") : "thread " + std::to_string(tid);
}

// Writes every byte of n bytes of stack so the pages are mapped (and, after mlockall, locked).
// noinline keeps the frame real; the volatile pointer keeps the stores.
__attribute__((noinline)) void touch_stack(std::size_t n) {
  volatile unsigned char* p = static_cast<unsigned char*>(alloca(n));
  for (std::size_t i = 0; i < n; i += 64) p[i] = 0;
  if (n > 0) p[n - 1] = 0;
}

}  // namespace

SetupStatus pin_thread_to_cpu(pid_t tid, int cpu) {
  const long n = sysconf(_SC_NPROCESSORS_CONF);
  if (cpu < 0 || cpu >= n || cpu >= CPU_SETSIZE)
    return failed("CPU " + std::to_string(cpu) + " does not exist (this machine has " +
                  std::to_string(n) + ")");
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (sched_setaffinity(tid, sizeof set, &set) != 0)
    return failed("cannot pin " + thread_name(tid) + " to CPU " + std::to_string(cpu) + ": " +
                  errno_text(errno));
  return ok("pinned " + thread_name(tid) + " to CPU " + std::to_string(cpu));
}

SetupStatus pin_current_thread_to_cpu(int cpu) {
  return pin_thread_to_cpu(0, cpu);
}

SetupStatus lock_memory_and_prefault_stack(std::size_t stack_bytes) {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    const int err = errno;
    return failed("mlockall failed (" + errno_text(err) +
                  "): memory is not locked; page faults may stall the loop "
                  "(run as root or raise RLIMIT_MEMLOCK)");
  }
  // Freed memory stays in the (locked) heap instead of going back to the kernel, and large
  // blocks come from the heap instead of fresh mmaps, so a later allocation cannot page-fault.
  mallopt(M_TRIM_THRESHOLD, -1);
  mallopt(M_MMAP_MAX, 0);
  touch_stack(stack_bytes);
  return ok("memory locked (mlockall current+future), " + std::to_string(stack_bytes / 1024) +
            " KiB of stack prefaulted");
}

SetupStatus try_set_thread_fifo_priority(pid_t tid, int priority) {
  const int lo = sched_get_priority_min(SCHED_FIFO), hi = sched_get_priority_max(SCHED_FIFO);
  if (priority < lo || priority > hi)
    return failed("SCHED_FIFO priority " + std::to_string(priority) + " is outside " +
                  std::to_string(lo) + ".." + std::to_string(hi));
  sched_param param{};
  param.sched_priority = priority;
  if (sched_setscheduler(tid, SCHED_FIFO, &param) != 0) {
    const int err = errno;
    std::string why = errno_text(err);
    if (err == EPERM) {
      rlimit lim{};
      getrlimit(RLIMIT_RTPRIO, &lim);
      why += " (not root, no CAP_SYS_NICE, RLIMIT_RTPRIO is " +
             (lim.rlim_cur == RLIM_INFINITY ? std::string("unlimited")
                                            : std::to_string(lim.rlim_cur)) +
             ")";
    }
    return failed("SCHED_FIFO priority " + std::to_string(priority) + " not permitted for " +
                  thread_name(tid) + ": " + why + "; running at normal priority");
  }
  return ok(thread_name(tid) + " runs SCHED_FIFO at priority " + std::to_string(priority));
}

SetupStatus try_set_fifo_priority(int priority) {
  return try_set_thread_fifo_priority(0, priority);
}

SetupStatus set_minimal_timer_slack() {
  if (prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) != 0)
    return failed("cannot set timer slack: " + errno_text(errno));
  return ok("timer slack 1 ns");
}

std::vector<pid_t> process_thread_ids() {
  std::vector<pid_t> ids;
  if (DIR* dir = opendir("/proc/self/task")) {
    while (const dirent* e = readdir(dir))
      if (e->d_name[0] != '.') ids.push_back(static_cast<pid_t>(std::atoi(e->d_name)));
    closedir(dir);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

CpuDmaLatencyHold::CpuDmaLatencyHold() {
  fd_ = open("/dev/cpu_dma_latency", O_RDWR | O_CLOEXEC);
  if (fd_ < 0) {
    message_ =
        "/dev/cpu_dma_latency not held (" + errno_text(errno) + "): idle CPUs may wake up slowly";
    return;
  }
  // The kernel keeps the request while the file stays open; the value is a binary s32 in us.
  const std::int32_t zero = 0;
  if (write(fd_, &zero, sizeof zero) != static_cast<ssize_t>(sizeof zero)) {
    message_ = "/dev/cpu_dma_latency not held (write: " + errno_text(errno) + ")";
    close(fd_);
    fd_ = -1;
    return;
  }
  message_ = "/dev/cpu_dma_latency held at 0 us";
}

CpuDmaLatencyHold::~CpuDmaLatencyHold() {
  if (fd_ >= 0) close(fd_);
}

std::string RealtimeReport::describe() const {
  std::string s;
  for (const SetupStatus* st : {&affinity, &memory, &priority, &denormals})
    if (!st->message.empty()) s += (st->ok ? "  ok    " : "  WARN  ") + st->message + "\n";
  return s;
}

RealtimeReport apply_realtime_setup(const RealtimeOptions& options) {
  RealtimeReport r;
  if (options.cpu >= 0) r.affinity = pin_current_thread_to_cpu(options.cpu);
  if (options.lock_memory) r.memory = lock_memory_and_prefault_stack(options.prefault_stack_bytes);
  if (options.fifo_priority > 0) {
    r.priority = try_set_fifo_priority(options.fifo_priority);
    r.fifo = r.priority.ok;
  }
  if (!r.fifo) {
    const SetupStatus slack = set_minimal_timer_slack();
    const std::string normal = options.fifo_priority > 0 ? r.priority.message + "; "
                                                         : std::string("SCHED_OTHER (asked); ");
    r.priority = {options.fifo_priority == 0 && slack.ok, normal + slack.message};
  }
  r.denormals = flush_denormals_to_zero();
  return r;
}

}  // namespace flexloop::rt
