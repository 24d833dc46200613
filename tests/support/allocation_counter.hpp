// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Counts the heap allocations of the test thread with the programs' own counting allocator
// (rt/counting_malloc, rt/thread_allocations.hpp): glibc's malloc family, and operator new
// through it. Linked into tests/alloc's executable only where it is linked into the programs:
// not under the sanitizers, which interpose the same functions.
#include <cstdint>

#include "rt/thread_allocations.hpp"

namespace flexloop::test {

/// Allocations (malloc family and operator new) made by the calling thread so far.
inline std::uint64_t allocation_count() noexcept {
  return rt::thread_allocations();
}

}  // namespace flexloop::test
