// SPDX-License-Identifier: BSD-3-Clause
#include "rt/transport_kind.hpp"

#include "rt/enum_names.hpp"

namespace flexloop::rt {

namespace {
constexpr EnumName<TransportKind> kTransportNames[] = {{TransportKind::kLcm, "lcm"},
                                                       {TransportKind::kIceoryx, "iceoryx"}};
}  // namespace

TransportKind parse_transport(const std::string& name) {
  return parse_enum(kTransportNames, name, "transport");
}

const char* to_string(TransportKind kind) {
  return enum_name(kTransportNames, kind);
}

}  // namespace flexloop::rt
