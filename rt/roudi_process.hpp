// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// RouDi, iceoryx's daemon, as a component of a run (issue 48). iceoryx 2.0 keeps one RouDi per
// host: it owns the shared memory (/dev/shm/iceoryx_mgmt and one data segment, named after the
// segment's group) and the registration socket /tmp/roudi, and holds the flock
// /tmp/iox-unique-roudi.lock while it runs. 2.0 has no domain or instance id, so two runs on one
// host cannot each have their own: a RouDi that already runs is refused with its pid, and tests
// that start one are serialised.
//
// RoudiProcess starts `iox-roudi -c <config>` with a config written for the run's messages, in a
// process group of its own (a terminal's SIGINT reaches the run, not RouDi: the run stops it),
// with PR_SET_PDEATHSIG so that it ends when its parent dies, its output in a log file; waits
// until RouDi says it is ready for clients, then removes the config and the log from the disk
// (the log stays readable through an open descriptor); and stops it by its pid (SIGTERM, then
// SIGKILL after the grace time) on stop() or destruction. When it had to be killed, the segments it
// logged, its socket and its lock files are removed, so nothing is left behind on any path we
// control.
//
// Stop the run's iceoryx processes before RouDi: on SIGTERM RouDi asks every process still
// registered to terminate as well.
#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace flexloop::rt {

/// Why RouDi could not be started or was lost: the message names iox-roudi and says what to do.
struct RoudiError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One mempool of the config: chunks of `chunk_bytes` payload (a multiple of 8), `count` of them.
struct RoudiMempool {
  std::uint32_t chunk_bytes = 0;
  std::uint32_t count = 0;
};

/// A single mempool whose chunks hold the largest message (rounded up to a 64-byte cache line).
std::vector<RoudiMempool> mempools_for_messages(std::size_t largest_message_bytes,
                                                std::uint32_t count);

/// The RouDi config (TOML, format version 1 of iceoryx 2.0): one segment with these mempools.
/// std::invalid_argument for no mempool, a zero count or a chunk size that is not a multiple of 8.
std::string roudi_config_toml(const std::vector<RoudiMempool>& mempools);

/// iceoryx 2.0's fixed names on Linux (iceoryx_hoofs/platform/platform_settings.hpp and
/// iceoryx_posh/iceoryx_posh_types.hpp; tests/iceoryx checks them against the headers).
inline constexpr const char* kRoudiLockFile = "/tmp/iox-unique-roudi.lock";
inline constexpr const char* kRoudiSocket = "/tmp/roudi";
inline constexpr const char* kRoudiSocketLock = "/tmp/roudi.lock";
inline constexpr const char* kRoudiManagementSegment = "iceoryx_mgmt";

/// The pid of the RouDi that holds kRoudiLockFile now, if any (read from /proc/locks).
std::optional<pid_t> running_roudi_pid();

struct RoudiOptions {
  std::string executable = "iox-roudi";  // looked up on PATH unless it holds a '/'
  std::vector<RoudiMempool> mempools = mempools_for_messages(512, 256);
  /// RouDi's watch of its clients' keep-alive messages. Off for a loop's RouDi: hil stops the
  /// controller process (SIGSTOP) between loop segments, and two spinning SCHED_FIFO loops can
  /// starve the keep-alive threads, either of which RouDi would take for a dead client and
  /// disconnect. The run's RouDi ends with the run, so nothing is lost by not watching.
  bool monitoring = true;
  std::int64_t ready_timeout_ns = 5'000'000'000;
  std::int64_t stop_grace_ns = 3'000'000'000;
};

class RoudiProcess {
 public:
  /// Writes the config into a fresh folder under $TMPDIR (or /tmp), starts RouDi and waits until
  /// it is ready. RoudiError when one already runs, the program cannot be started, or it ends or
  /// stays silent before it is ready (then it is killed and cleaned up).
  explicit RoudiProcess(const RoudiOptions& options);
  ~RoudiProcess();
  RoudiProcess(const RoudiProcess&) = delete;
  RoudiProcess& operator=(const RoudiProcess&) = delete;

  /// Stops RouDi by its pid (idempotent); afterwards nothing of it is left.
  void stop();
  /// False once RouDi has ended (checked without blocking).
  bool alive();
  /// "iox-roudi (pid N) ..." -- running, exited with status S, or killed by signal S.
  std::string describe();

  pid_t pid() const { return pid_; }
  /// RouDi's output so far (iceoryx's log lines).
  std::string log() const;

 private:
  void start(const RoudiOptions& options);
  void wait_until_ready(std::int64_t timeout_ns);
  void remove_leftovers();
  void remove_folder();
  [[noreturn]] void fail(const std::string& why);

  pid_t pid_ = -1;
  std::optional<int> exit_status_;  // set once reaped
  bool stopped_ = false;
  std::int64_t stop_grace_ns_ = 0;
  int log_fd_ = -1;  // RouDi's output, read-only
  std::string folder_, config_path_, log_path_;
};

}  // namespace flexloop::rt
