// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Number checks for command-line options. CLI11's PositiveNumber and Range let NaN through (every
// comparison with NaN is false), and PositiveNumber takes "inf": a duration of "nan" then fell
// back to the scene's silently. These refuse both, with the option's text in the message.
#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace flexloop::cli {

/// A finite number in [lo, hi].
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v))
          return "'" + text + "' is not a finite number";
        if (v < lo || v > hi)
          return "'" + text + "' is not in [" + CLI::detail::to_string(lo) + ", " +
                 CLI::detail::to_string(hi) + "]";
        return {};
      },
      "FLOAT in [" + CLI::detail::to_string(lo) + " - " + CLI::detail::to_string(hi) + "]");
}

/// A finite number > 0.
inline CLI::Validator finite_positive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || !(v > 0))
          return "'" + text + "' is not a finite number > 0";
        return {};
      },
      "POSITIVE");
}

}  // namespace flexloop::cli
