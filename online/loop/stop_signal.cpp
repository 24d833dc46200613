// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/stop_signal.hpp"

#include <signal.h>

namespace flexloop::loop {

namespace {
volatile sig_atomic_t g_stop = 0;
void on_stop(int) {
  g_stop = 1;
}
}  // namespace

void install_stop_handlers() {
  g_stop = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stop_requested() noexcept {
  return g_stop != 0;
}

}  // namespace flexloop::loop
