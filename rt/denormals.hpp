// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Denormal (subnormal) numbers flushed to zero on the calling thread: results below the smallest
// normal number become 0 (FTZ) and subnormal operands are read as 0 (DAZ). A lightly damped plant
// decaying towards rest passes through the subnormal range (float below 1.2e-38), where x86 takes
// a microcode assist of ~100 cycles per operation: a step that costs 40 ns could cost microseconds
// just as the machine comes to rest. Flushing changes results only below 1.2e-38 (float) or
// 2.2e-308 (double), far under any sensor's resolution.
//
// The setting is per thread (MXCSR on x86, FPCR on AArch64) and is inherited by threads created
// after it. apply_realtime_setup() (realtime_setup.hpp) applies it to every real-time thread.
#include "rt/realtime_setup.hpp"

namespace flexloop::rt {

/// Sets FTZ and DAZ for the calling thread; on a CPU without them, says so (ok = false).
SetupStatus flush_denormals_to_zero();

/// True when the calling thread flushes subnormal results and operands to zero.
bool denormals_flushed() noexcept;

}  // namespace flexloop::rt
