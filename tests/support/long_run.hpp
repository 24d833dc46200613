// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Long runs under the sanitizers (tools/sanitize: ASan + UBSan at -O1, 20x slower on these loops)
// take a tenth of their length: what the sanitizers look for, an access out of bounds or undefined
// arithmetic, lies on the path every step takes, and a tenth of the run takes it too. The bounds
// over the full length (drift, rounding, statistics) are the ordinary build's, where tools/check
// runs every test at the length its name states.
#include <cmath>

#include "common/address_sanitizer.hpp"

namespace flexloop::test {

#if defined(FLEXLOOP_ADDRESS_SANITIZER)
inline constexpr long kSanitizerShare = 10;
#else
inline constexpr long kSanitizerShare = 1;
#endif

// The step count of a long deterministic run.
constexpr long long_run_steps(long steps) {
  return steps / kSanitizerShare;
}

// A statistical run: its length and the tolerance of the average it judges. The tolerance widens
// with the square root of the share, as an average's scatter goes with one over the square root
// of its length.
struct StatisticalRun {
  double seconds;
  double tolerance;
};

inline StatisticalRun statistical_run(double seconds, double tolerance) {
  const auto share = static_cast<double>(kSanitizerShare);
  return {seconds / share, tolerance * std::sqrt(share)};
}

}  // namespace flexloop::test
