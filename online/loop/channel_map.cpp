// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/channel_map.hpp"

#include "artefact/loop_artefact.hpp"

namespace flexloop::loop {

nlohmann::json channel_map_json(const artefact::LoopArtefact& loop) {
  const nlohmann::json a = artefact::to_json(loop);
  return {{"format", "flexloop channel map"},
          {"loop", loop.name},
          {"rate_hz", loop.rate_hz},
          {"controller", artefact::to_string(loop.controller)},
          {"channels", a["channels"]},
          {"provenance", a["provenance"]},
          {"messages",
           {{"FLEXLOOP_SENSOR",
             {{"sensors", "channels.sensors"}, {"performance", "channels.performance"}}},
            {"FLEXLOOP_COMMAND", {{"commands", "channels.actuators"}}}}}};
}

}  // namespace flexloop::loop
