#pragma once
// Counts every heap allocation of the process: the test executable that includes
// allocation_counter.cpp replaces malloc, calloc, realloc, the aligned allocators (forwarding to
// glibc's __libc_* entry points; glibc 2.36 has no malloc hooks) and every global operator new.
// Include it in one executable only (tests/alloc), and not under the sanitizers, which interpose
// the same functions.
#include <cstdint>

namespace flexloop::test {

/// Allocations (malloc family and operator new) since the program started.
std::uint64_t allocation_count() noexcept;

}  // namespace flexloop::test
