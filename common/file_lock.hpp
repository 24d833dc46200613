// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// An exclusive advisory lock on a file, taken without waiting (flock(2): held by one open file
// description, released when it is closed or its process dies, however it dies), and who holds
// it: the pid /proc/locks gives for the file's device and inode. A holder on another host of a
// network file system is not seen there.
#include <sys/types.h>

#include <memory>
#include <optional>
#include <string>

namespace flexloop::common {

/// The pid of the process on this host that holds a flock on `path`, if any.
std::optional<pid_t> flock_holder(const std::string& path);

class ExclusiveFileLock {
 public:
  /// Opens `path` (created if missing, never truncated) and takes its lock: nullptr when another
  /// open file holds it. @throws std::runtime_error when the file cannot be opened.
  static std::unique_ptr<ExclusiveFileLock> try_take(const std::string& path);
  ~ExclusiveFileLock();
  ExclusiveFileLock(const ExclusiveFileLock&) = delete;
  ExclusiveFileLock& operator=(const ExclusiveFileLock&) = delete;

 private:
  explicit ExclusiveFileLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace flexloop::common
