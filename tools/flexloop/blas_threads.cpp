// SPDX-License-Identifier: BSD-3-Clause
#include "tools/flexloop/blas_threads.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <string>

namespace flexloop::cli {

int set_blas_threads() {
  // Looked up, not linked: the reference BLAS (and MKL) have no such function.
  using SetThreads = void (*)(int);
  const auto set = reinterpret_cast<SetThreads>(::dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return 0;
  int threads = 1;
  if (const char* wanted = std::getenv("FLEXLOOP_BLAS_THREADS")) {
    try {
      threads = std::max(1, std::stoi(wanted));
    } catch (const std::exception&) {
      threads = 1;  // not a number: the default
    }
  }
  set(threads);
  return threads;
}

}  // namespace flexloop::cli
