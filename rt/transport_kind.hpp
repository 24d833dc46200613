// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Which carrier a loop's messages travel on (issue 48): LCM (UDP multicast; the default, and the
// only one between hosts) or iceoryx (same-host shared memory, rt/iceoryx_transport.hpp). The
// messages, their validation and the stations are the same on both (rt/loop_transport.hpp).
#include <string>

namespace flexloop::rt {

enum class TransportKind { kLcm, kIceoryx };

/// "lcm" | "iceoryx" -> kind; std::invalid_argument naming the choices otherwise.
TransportKind parse_transport(const std::string& name);
const char* to_string(TransportKind kind);

}  // namespace flexloop::rt
