// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The in-process closed loop of `flexloop sim`: the plant with its simulated hardware
// (plant/runtime/simulated_hardware.hpp) and the PI controller, stepped as fast as the machine
// allows, with the sampling convention of the real-time loop:
//
//   reading_k = hardware.sample()          floor, plant outputs with the held force, sensors
//   u_k       = controller.step(reading_k.sensors)   (0 when Controller is NoEffect)
//   hardware.apply(u_k)                    actuator, plant advance
//
// The loop runs in chunks (progress is reported between chunks, never inside one); inside a
// chunk a step allocates nothing, takes no lock and makes no system call. The log (every
// `log_every`-th sample) and the RMS accumulators are sized before the loop.
//
// A loop that diverges stops at the first sample whose performance outputs and command leave
// the stated range (plant/runtime/divergence.hpp): RunResult::divergence says when and where, and
// the caller reports it as a failure instead of printing meaningless RMS values.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>

#include "controller/runtime/loop_controller.hpp"
#include "online/sim/run_log.hpp"
#include "plant/runtime/divergence.hpp"
#include "plant/runtime/simulated_hardware.hpp"

namespace flexloop::sim {

struct RunSettings {
  long steps = 0;
  double dt = 0;
  long log_every = 0;          ///< 0: no log
  long chunk_steps = 100'000;  ///< steps between progress reports, >= 1
};

using plant::runtime::Divergence;
using plant::runtime::kDivergenceLimit;

struct RunResult {
  Eigen::VectorXd rms_performance;  ///< RMS of each true performance output z_i
  Eigen::VectorXd rms_command;      ///< RMS of each actuator command
  /// Rows: t, floor (NW), performance (NZ), performance sensors (NZ), sensors (NS), commands (NC).
  RunLog log;
  double loop_seconds = 0;  ///< wall time of the stepping alone
  Divergence divergence;    ///< the RMS values cover the samples up to it
  /// What the controller said of its run (loop_controller.hpp: a controller FMU's failed call,
  /// warnings and log); empty without a controller.
  controller::runtime::ControllerReport controller;
};

/// Log columns of a run, for the header of a CSV file.
inline Eigen::Index log_columns(Eigen::Index nw, Eigen::Index nz, Eigen::Index ns,
                                Eigen::Index nc) {
  return 1 + nw + 2 * nz + ns + nc;
}

/// Hardware: plant/runtime/simulated_hardware.hpp (compiled or start-up-sized counts alike).
/// Controller: anything with step(sensors) -> command, or NoEffect (a zero command).
template <class Hardware, class Controller>
RunResult run_closed_loop(Hardware hw, Controller controller, const RunSettings& s,
                          const std::function<void(long done, long total)>& progress) {
  static_assert(
      !plant::runtime::kPresent<Controller> || controller::runtime::LoopController<Controller>,
      "run_closed_loop: the controller implements controller/runtime/loop_controller.hpp");
  using Command = typename Hardware::Command;
  using Performance = typename Hardware::Performance;
  const Eigen::Index nw = hw.disturbances(), nc = hw.actuators(), nz = hw.performance_outputs(),
                     ns = hw.sensors();

  RunResult r;
  const long log_rows = s.log_every > 0 ? (s.steps + s.log_every - 1) / s.log_every : 0;
  r.log = RunLog(log_rows, log_columns(nw, nz, ns, nc));
  RunLog::View log = r.log.matrix();
  Performance sum_z2 = Performance::Zero(nz);
  Command sum_u2 = Command::Zero(nc), u = Command::Zero(nc);
  long row = 0;

  const auto start = std::chrono::steady_clock::now();
  const long chunk = std::max(s.chunk_steps, 1L);
  for (long begin = 0, end = 0; begin < s.steps && !r.divergence.happened(); begin = end) {
    end = begin + std::min(chunk, s.steps - begin);
    for (long k = begin; k < end; ++k) {
      const auto& reading = hw.sample();
      if constexpr (plant::runtime::kPresent<Controller>) u = controller.step(reading.sensors);
      hw.apply(u);
      if (plant::runtime::beyond_range(hw.performance(), u)) {
        r.divergence = plant::runtime::locate_divergence(k, s.dt, hw.performance(), u);
        break;
      }
      sum_z2 += hw.performance().cwiseAbs2();
      sum_u2 += u.cwiseAbs2();
      if (s.log_every > 0 && k % s.log_every == 0) {
        auto line = log.row(row++);
        line(0) = static_cast<double>(k) * s.dt;
        line.segment(1, nw) = hw.floor_acceleration().transpose().template cast<double>();
        line.segment(1 + nw, nz) = hw.performance().transpose().template cast<double>();
        line.segment(1 + nw + nz, nz) = reading.performance.transpose().template cast<double>();
        line.segment(1 + nw + 2 * nz, ns) = reading.sensors.transpose().template cast<double>();
        line.segment(1 + nw + 2 * nz + ns, nc) = u.transpose().template cast<double>();
      }
    }
    if (progress && !r.divergence.happened()) progress(end, s.steps);
  }
  r.loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (r.divergence.happened()) r.log.keep_rows(row);  // the rows written
  // Samples 0 .. step-1 were summed when it diverged at `step`.
  const double n =
      static_cast<double>(std::max(r.divergence.happened() ? r.divergence.step : s.steps, 1L));
  r.rms_performance = (sum_z2.template cast<double>() / n).cwiseSqrt();
  r.rms_command = (sum_u2.template cast<double>() / n).cwiseSqrt();
  if constexpr (plant::runtime::kPresent<Controller>) r.controller = controller.report();
  return r;
}

}  // namespace flexloop::sim
