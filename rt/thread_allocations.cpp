// SPDX-License-Identifier: BSD-3-Clause
#include "rt/thread_allocations.hpp"

// Defined by rt/counting_malloc when the program links it; a null address otherwise.
extern "C" std::uint64_t flexloop_counting_malloc_thread_allocations() noexcept
    __attribute__((weak));

namespace flexloop::rt {

bool allocations_counted() noexcept {
  return flexloop_counting_malloc_thread_allocations != nullptr;
}

std::uint64_t thread_allocations() noexcept {
  return allocations_counted() ? flexloop_counting_malloc_thread_allocations() : 0;
}

}  // namespace flexloop::rt
