// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Asks tests/campaign/reference.py (OpenTURNS, SciPy) for an outside reference: writes the
// request, runs Debian's python3 on it (the tests run from the repository root), reads the answer.
#include <nlohmann/json.hpp>

namespace flexloop::campaign::test {

/// The answer of reference.py to `request` ({"task": ..., ...}); throws std::runtime_error with
/// python's exit status when it fails.
nlohmann::json outside_reference(const nlohmann::json& request);

}  // namespace flexloop::campaign::test
