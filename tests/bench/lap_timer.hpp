// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Phase timing inside one benchmark iteration: lap(acc) adds the time since the previous lap (or
// since construction) to acc. The clock is this thread's CPU time, so a phase's figure stays the
// work it did when other processes share the core (wall time would count their slices too).
#include <time.h>

namespace flexloop::bench {

class LapTimer {
 public:
  LapTimer() : last_(now()) {}
  void restart() { last_ = now(); }
  void lap(double& acc) {
    const double t = now();
    acc += t - last_;
    last_ = t;
  }

 private:
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  double last_;
};

}  // namespace flexloop::bench
