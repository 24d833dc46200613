// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Settings shared by the plant and controller processes (flexloop plant | controller | hil):
// clock and wait mode, CPU and priority, safe-command threshold, carrier and LCM URL, channels,
// and the private link allowed besides loopback (online/loop/private_network.hpp).
#include <cstdint>
#include <functional>
#include <string>

#include "online/loop/loop_status.hpp"
#include "online/loop/run_verdict.hpp"
#include "online/sim/loop_start.hpp"
#include "rt/lcm_transport.hpp"
#include "rt/periodic_clock.hpp"
#include "rt/realtime_setup.hpp"
#include "rt/transport_kind.hpp"

namespace flexloop::loop {

struct LoopChannels {
  std::string sensor = "FLEXLOOP_SENSOR";    // sensor_sample_t, plant -> controller
  std::string command = "FLEXLOOP_COMMAND";  // actuator_command_t, controller -> plant
  std::string stats = "FLEXLOOP_STATS";      // loop_stats_t, plant, once a second
};

struct LoopOptions {
  std::string loop_path;  ///< a scene (TOML) or a loop artefact (JSON)
  double rate_hz = 0;     ///< <= 0: the scene's [discretisation] rate (scenes only)
  double duration_s = 0;  ///< plant: <= 0: the scene's [run] duration; controller: 0 = until
                          ///< SIGINT/SIGTERM
  /// Hybrid by default: sleep until the spin margin before a deadline or an expected message,
  /// then spin; a sleeping loop pays one timer or socket wake-up per message (tens of us on a
  /// VM), which at 10 kHz is most of the period.
  rt::WaitMode wait = rt::WaitMode::kHybrid;
  /// Who reads the socket: the loop thread itself by default (LCM's receive thread adds a
  /// wake-up per message, see rt/lcm_direct_socket.hpp and doc/performance.md).
  rt::ReceivePath receive_path = rt::ReceivePath::kDirect;
  std::int64_t spin_margin_ns = rt::kDefaultSpinMarginNs;
  rt::RealtimeOptions realtime{.cpu = 0, .fifo_priority = 80};
  int safe_after = 10;  ///< consecutive missed answers before the safe command
  /// Plant: the safe command ramps the held answer to zero over this time [s]; 0: zero at once.
  double safe_ramp_s = 0.5;
  /// The carrier of the loop's messages: LCM, or iceoryx's shared memory on this host (a RouDi
  /// must run: `flexloop roudi`, or hil starts one).
  rt::TransportKind transport = rt::TransportKind::kLcm;
  /// Plant over iceoryx: wait this long at start-up for a controller's subscription and answer
  /// to be connected (RouDi connects them some ms after both exist); 0: do not wait (the plant
  /// alone). Unused over LCM, which has no connections.
  double connect_timeout_s = 2.0;
  std::string url;   ///< empty: see loop_lcm_url()
  std::string link;  ///< a veth allowed besides lo (two-namespace runs)
  LoopChannels channels;
  /// Plant and controller: the loop's stationary start (online/sim/loop_start.hpp), or rest.
  sim::StartKind start = sim::StartKind::kStationary;
  bool quiet = false;            ///< no start-up banner
  LoopStatus* status = nullptr;  ///< plant: also write the once-a-second figures here
  RunLimits limits;  ///< the plant's verdict and overrun policy (online/loop/run_verdict.hpp)
  /// Plant: the run in this many segments of equal length; between two, outside any cycle,
  /// between_segments is called and the grid stands still until it returns (hil measures a
  /// baseline segment there, online/hil/interleaved_baselines.hpp).
  int segments = 1;
  std::function<void()> between_segments;
  /// Plant: record every message it sends and receives, after the loop's channel map, into this
  /// LCM log file (rt/event_log_recorder.hpp); empty: no log.
  std::string lcm_log;
};

}  // namespace flexloop::loop
