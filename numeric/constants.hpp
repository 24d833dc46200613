// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Mathematical constants, defined once for the project (what many files had written as their own
// file-local copies): pi from C++20's <numbers>, the machine epsilon of double.
#include <limits>
#include <numbers>

namespace flexloop::numeric {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2 * std::numbers::pi;
/// The spacing of doubles at 1 (2^-52).
inline constexpr double kEps = std::numeric_limits<double>::epsilon();

}  // namespace flexloop::numeric
