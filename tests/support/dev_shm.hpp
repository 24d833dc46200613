// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The names in /dev/shm (POSIX shared-memory segments of the whole host), for tests that check
// a run left no segment behind: compare the set before and after.
#include <filesystem>
#include <set>
#include <string>

namespace flexloop::test {

inline std::set<std::string> dev_shm_entries() {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator("/dev/shm"))
    names.insert(e.path().filename().string());
  return names;
}

}  // namespace flexloop::test
