// SPDX-License-Identifier: BSD-3-Clause
#include "rt/denormals.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif
#include <cstdint>

namespace flexloop::rt {

#if defined(__aarch64__)
namespace {
constexpr std::uint64_t kFpcrFlushToZero = 1ULL << 24;  // FZ: both results and operands
std::uint64_t read_fpcr() noexcept {
  std::uint64_t v;
  asm volatile("mrs %0, fpcr" : "=r"(v));
  return v;
}
}  // namespace
#endif

SetupStatus flush_denormals_to_zero() {
#if defined(__x86_64__) || defined(__i386__)
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  return {denormals_flushed(), "denormals flushed to zero (FTZ, DAZ)"};
#elif defined(__aarch64__)
  const std::uint64_t v = read_fpcr() | kFpcrFlushToZero;
  asm volatile("msr fpcr, %0" : : "r"(v));
  return {denormals_flushed(), "denormals flushed to zero (FPCR.FZ)"};
#else
  return {false, "denormals not flushed: no flush-to-zero control known for this CPU"};
#endif
}

bool denormals_flushed() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  return _MM_GET_FLUSH_ZERO_MODE() == _MM_FLUSH_ZERO_ON &&
         _MM_GET_DENORMALS_ZERO_MODE() == _MM_DENORMALS_ZERO_ON;
#elif defined(__aarch64__)
  return (read_fpcr() & kFpcrFlushToZero) != 0;
#else
  return false;
#endif
}

}  // namespace flexloop::rt
