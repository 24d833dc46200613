// SPDX-License-Identifier: BSD-3-Clause
#include "rt/loop_transport.hpp"

#include <algorithm>
#include <flexloop_msgs/loop_stats_t.hpp>

namespace flexloop::rt {

LoopTransport::LoopTransport(const LoopTransportOptions& o) : url_(o.url) {
  if (o.kind == TransportKind::kLcm)
    lcm_ = std::make_unique<LcmTransport>(o.url, o.receive_path);
  else
    iceoryx_ = std::make_unique<IceoryxTransport>(o.runtime_name);
}

std::string LoopTransport::describe() const {
  return lcm_ ? "LCM " + url_ : std::string("iceoryx (shared memory)");
}

RoudiOptions loop_roudi_options() {
  const flexloop_msgs::loop_stats_t stats{};
  const int largest =
      std::max({max_encoded_size<flexloop_msgs::sensor_sample_t>(),
                max_encoded_size<flexloop_msgs::actuator_command_t>(), stats.getEncodedSize()});
  RoudiOptions o;
  o.monitoring = false;  // see RoudiOptions::monitoring
  o.mempools = mempools_for_messages(static_cast<std::size_t>(largest), 256);
  return o;
}

LoopProcessSetup set_up_loop_process(LoopTransport& transport, const RealtimeOptions& options) {
  if (LcmTransport* lcm = transport.lcm()) return set_up_loop_process(*lcm, options);
  const RealtimeReport report = apply_realtime_setup(options);
  return {report.fifo, report.describe()};
}

}  // namespace flexloop::rt
