// Replacement allocation functions that count (see tests/support/allocation_counter.hpp).
// operator new forwards to the counting malloc, so each allocation is counted exactly once.
#include "tests/support/allocation_counter.hpp"

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <new>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
}

namespace {

std::atomic<std::uint64_t> g_allocations{0};

void* counted(void* p) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return p;
}

void* new_or_throw(std::size_t n) {
  void* p = std::malloc(n == 0 ? 1 : n);
  if (!p) throw std::bad_alloc();
  return p;
}

void* aligned_new_or_throw(std::size_t n, std::align_val_t a) {
  void* p = std::aligned_alloc(static_cast<std::size_t>(a), n == 0 ? 1 : n);
  if (!p) throw std::bad_alloc();
  return p;
}

}  // namespace

std::uint64_t flexloop::test::allocation_count() noexcept {
  return g_allocations.load(std::memory_order_relaxed);
}

extern "C" {
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
int posix_memalign(void** out, std::size_t a, std::size_t n) noexcept {
  *out = counted(__libc_memalign(a, n));
  return *out ? 0 : ENOMEM;
}
}

void* operator new(std::size_t n) {
  return new_or_throw(n);
}
void* operator new[](std::size_t n) {
  return new_or_throw(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return std::malloc(n ? n : 1);
}
void* operator new(std::size_t n, std::align_val_t a) {
  return aligned_new_or_throw(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return aligned_new_or_throw(n, a);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
