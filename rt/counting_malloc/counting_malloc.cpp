// SPDX-License-Identifier: BSD-3-Clause
// The counting allocator of rt/thread_allocations.hpp: glibc's allocation functions, each
// forwarding to glibc's own (__libc_*) after one increment of a thread-local counter. Linked
// into the programs that run a controller process (an object of the executable: its malloc is
// the one every library, a dlopen'ed FMU included, resolves to). Not in sanitizer builds.
// operator new reaches it through malloc (libstdc++'s operator new calls malloc).
#include <cerrno>
#include <cstddef>
#include <cstdint>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void* __libc_pvalloc(std::size_t);
void __libc_free(void*);
}

namespace {

// Local-exec TLS in the executable: no allocation, no call, usable from the first malloc on.
constinit thread_local std::uint64_t t_allocations = 0;

void* counted(void* p) noexcept {
  ++t_allocations;
  return p;
}

}  // namespace

extern "C" {

std::uint64_t flexloop_counting_malloc_thread_allocations() noexcept {
  return t_allocations;
}

void* malloc(std::size_t n) noexcept {
  return counted(__libc_malloc(n));
}
void* calloc(std::size_t n, std::size_t size) noexcept {
  return counted(__libc_calloc(n, size));
}
void* realloc(void* p, std::size_t n) noexcept {
  return counted(__libc_realloc(p, n));
}
void free(void* p) noexcept {
  __libc_free(p);
}
void* memalign(std::size_t a, std::size_t n) noexcept {
  return counted(__libc_memalign(a, n));
}
void* aligned_alloc(std::size_t a, std::size_t n) noexcept {
  return counted(__libc_memalign(a, n));
}
void* valloc(std::size_t n) noexcept {
  return counted(__libc_valloc(n));
}
void* pvalloc(std::size_t n) noexcept {
  return counted(__libc_pvalloc(n));
}
int posix_memalign(void** out, std::size_t a, std::size_t n) noexcept {
  // glibc's checks: a power of two, a multiple of sizeof(void*).
  if (a % sizeof(void*) != 0 || (a & (a - 1)) != 0) return EINVAL;
  void* p = __libc_memalign(a, n);
  if (!p) return ENOMEM;
  *out = counted(p);
  return 0;
}

}  // extern "C"
