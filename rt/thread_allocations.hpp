// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How many allocations this thread has made: what the controller process counts around each
// answer, so that its report can say whether a controller it cannot see into (an FMU) keeps the
// promise "a step never allocates" (controller/runtime/loop_controller.hpp).
//
// Counted only in a program that links the counting allocator (rt/counting_malloc: `flexloop`
// and `flexloop-controller`, not under the sanitizers, whose runtime owns malloc). Elsewhere
// allocations_counted() is false and the count stays 0. Reading it makes no system call and
// takes no lock.
#include <cstdint>

namespace flexloop::rt {

/// True when this program counts allocations (it links rt/counting_malloc).
bool allocations_counted() noexcept;

/// Allocations (malloc, calloc, realloc, memalign, aligned_alloc, posix_memalign, valloc,
/// pvalloc, and operator new through them) made by the calling thread so far; 0 when not counted.
std::uint64_t thread_allocations() noexcept;

}  // namespace flexloop::rt
