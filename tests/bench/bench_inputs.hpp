// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the closed-loop benchmarks share: the thread's CPU clock (read outside the timed loops,
// for the share of CPU time a benchmark got) and a fixed sequence of floor samples.
#include <Eigen/Core>
#include <ctime>
#include <random>
#include <vector>

namespace flexloop::bench {

/// CPU time of this thread [ns] (outside the timed loops only).
inline double thread_cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

/// Length of the floor sample sequence the loops cycle through.
inline constexpr int kSamples = 4096;

/// kSamples floor accelerations on the metrology frame's 6 channels (1 mm/s^2 rms, seed 1).
template <typename Scalar = double>
const std::vector<Eigen::Matrix<Scalar, 6, 1>>& floor_samples() {
  static const auto w = [] {
    std::mt19937 rng(1);
    std::normal_distribution<double> n01;
    std::vector<Eigen::Matrix<Scalar, 6, 1>> v(kSamples);
    for (auto& s : v)
      for (int i = 0; i < 6; ++i) s(i) = static_cast<Scalar>(1e-3 * n01(rng));
    return v;
  }();
  return w;
}

}  // namespace flexloop::bench
