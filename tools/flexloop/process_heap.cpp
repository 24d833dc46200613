// SPDX-License-Identifier: BSD-3-Clause
#include "tools/flexloop/process_heap.hpp"

#include <malloc.h>

namespace flexloop::cli {

void keep_freed_memory() {
  // 32 MiB: glibc's largest mmap threshold on 64-bit (a larger value is refused, and the
  // default's dynamic threshold would stay).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace flexloop::cli
