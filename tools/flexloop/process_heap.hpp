// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A command that builds and drops the same matrices thousands of times (a campaign's samples, a
// worst-machine search, subset simulation's chains) pays for glibc's defaults: its blocks above
// the mmap threshold are fresh mmaps, each page faulted in and unmapped again (TLB shootdowns to
// the other core), and freed memory is trimmed back to the kernel. Measured on 150 metrology-frame
// samples, one process: 2.13 s (0.5 s of it in the kernel) against 1.36 s with the heap kept,
// the same bytes out (doc/performance.md). So such commands keep their freed memory.
namespace flexloop::cli {

/// Blocks up to 32 MiB come from the heap, and up to 256 MiB of freed memory stays in it.
void keep_freed_memory();

}  // namespace flexloop::cli
