// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The timing tests that run `flexloop hil` enter a private loopback-only namespace first.
#include <catch2/catch.hpp>

#include <exception>

#include "online/hil/hil_run.hpp"

namespace flexloop::test {

/// Enters the namespace; false (with a warning) when this process cannot (not root).
inline bool in_private_network(const hil::HilOptions& o) {
  try {
    hil::prepare_hil_network(o);
    return true;
  } catch (const std::exception& e) {
    WARN("skipped: cannot enter a private network namespace: " << e.what());
    return false;
  }
}

}  // namespace flexloop::test
