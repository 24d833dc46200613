// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// How the stations of a real-time run start, from the artefact and the run's options: the one
// place the plant process (plant_loop_run.hpp), the controller process (controller_loop.cpp) and
// hil's replay of a run (online/hil/run_replay.hpp) take them from, so that all three start
// alike (same artefact, same seeds, same numbers).
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "artefact/loop_artefact.hpp"
#include "online/loop/loop_options.hpp"
#include "online/loop/plant_station.hpp"
#include "online/sim/loop_hardware.hpp"
#include "online/sim/loop_start.hpp"

namespace flexloop::loop {

/// The plant station's settings for a run of `loop` with options `o`, in plant run `epoch`.
inline PlantStationSettings plant_station_settings(const artefact::LoopArtefact& loop,
                                                   const LoopOptions& o, std::int64_t epoch) {
  const auto& actuator = loop.effects.actuator;
  return {.safe_after = o.safe_after,
          .epoch = epoch,
          .period_ns = static_cast<std::int64_t>(1e9 / loop.rate_hz + 0.5),
          .command_limit = actuator.present ? actuator.force_limit_n / std::abs(actuator.gain)
                                            : std::numeric_limits<double>::infinity(),
          .safe_ramp_periods = static_cast<std::int64_t>(o.safe_ramp_s * loop.rate_hz + 0.5)};
}

/// The plant's start: sets the hardware to the stationary draw (online/sim/loop_start.hpp) and
/// returns it, whose last command the station holds first; nullopt (hardware untouched): at rest.
template <class Hardware>
std::optional<sim::DrawnStart> start_plant_hardware(const artefact::LoopArtefact& loop,
                                                    sim::StartKind kind, Hardware& hw) {
  const auto& stationary = sim::run_start(loop);
  if (kind != sim::StartKind::kStationary || !stationary.exists()) return std::nullopt;
  sim::DrawnStart start = sim::draw_start(loop, stationary, sim::floor_filter_states(hw));
  sim::start_hardware_at(loop, start, hw);
  return start;
}

/// The controller's start: the same draw, from the artefact's floor; empty: at rest.
inline sim::DrawnStart controller_start(const artefact::LoopArtefact& loop, sim::StartKind kind) {
  const auto& stationary = sim::run_start(loop);
  if (kind != sim::StartKind::kStationary || !stationary.exists()) return {};
  return sim::draw_start(loop, stationary, sim::floor_start_states(loop));
}

}  // namespace flexloop::loop
