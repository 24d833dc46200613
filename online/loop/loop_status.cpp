// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/loop_status.hpp"

#include <sys/mman.h>

#include <new>
#include <stdexcept>

namespace flexloop::loop {

SharedLoopStatus::SharedLoopStatus() {
  void* page =
      mmap(nullptr, sizeof(LoopStatus), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (page == MAP_FAILED) throw std::runtime_error("cannot map the shared loop status");
  status_ = new (page) LoopStatus;
}

SharedLoopStatus::~SharedLoopStatus() {
  status_->~LoopStatus();
  munmap(status_, sizeof(LoopStatus));
}

}  // namespace flexloop::loop
