// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What a recorded run needs to be read: the loop, its rate and its channels (name, unit, order).
// It is the first message of a run's LCM log (UTF-8 JSON on kChannelMapChannel, not an lcm-gen
// type), so a log describes itself: a reader finds what each entry of FLEXLOOP_SENSOR and
// FLEXLOOP_COMMAND is beside the traffic (`flexloop log`, offline/report/run_log.hpp).
#include <nlohmann/json.hpp>

#include "artefact/loop_artefact.hpp"

namespace flexloop::loop {

inline constexpr const char* kChannelMapChannel = "FLEXLOOP_CHANNEL_MAP";

/// {"format": "flexloop channel map", "loop", "rate_hz", "controller", "channels",
///  "provenance", "messages": {which message field holds which channels}}.
nlohmann::json channel_map_json(const artefact::LoopArtefact& loop);

}  // namespace flexloop::loop
