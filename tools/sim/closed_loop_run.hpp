#pragma once
// The in-process closed loop of `flexloop sim`: the plant with its simulated hardware
// (plant/runtime/simulated_hardware.hpp) and the PI controller, stepped as fast as the machine
// allows, with the sampling convention of the real-time loop:
//
//   reading_k = hardware.sample()          floor, plant outputs with the held force, sensors
//   u_k       = controller.step(reading_k.force)   (0 when Controller is NoEffect)
//   hardware.apply(u_k)                    actuator, plant advance
//
// The loop runs in chunks (progress is reported between chunks, never inside one); inside a
// chunk a step allocates nothing, takes no lock and makes no system call. The log (every
// `log_every`-th sample) and the RMS accumulators are sized before the loop.
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>

#include "plant/runtime/simulated_hardware.hpp"

namespace flexloop::sim {

struct RunSettings {
  long steps = 0;
  double dt = 0;
  long log_every = 0;  ///< 0: no log
  int chunks = 20;     ///< progress granularity
};

struct RunResult {
  Eigen::VectorXd rms_performance;  ///< RMS of each true frame acceleration z_i
  Eigen::VectorXd rms_command;      ///< RMS of each actuator command
  /// Rows: t, floor (NW), frame (NZ), accelerometers (NZ), force sensors (NC), commands (NC).
  Eigen::MatrixXd log;
  double loop_seconds = 0;  ///< wall time of the stepping alone
};

/// Log columns of a run, for the header of a CSV file.
inline Eigen::Index log_columns(Eigen::Index nw, Eigen::Index nz, Eigen::Index nc) {
  return 1 + nw + 2 * nz + 2 * nc;
}

template <class Hardware, class Controller>
RunResult run_closed_loop(Hardware hw, Controller controller, const RunSettings& s,
                          const std::function<void(long done, long total)>& progress) {
  constexpr int NC = Hardware::Command::RowsAtCompileTime;
  constexpr int NZ = Hardware::Performance::RowsAtCompileTime;
  constexpr int NW = Hardware::Disturbance::RowsAtCompileTime;
  using Command = typename Hardware::Command;
  using Performance = typename Hardware::Performance;

  RunResult r;
  const long log_rows = s.log_every > 0 ? (s.steps + s.log_every - 1) / s.log_every : 0;
  r.log.setZero(log_rows, log_columns(NW, NZ, NC));
  Performance sum_z2 = Performance::Zero();
  Command sum_u2 = Command::Zero();
  long row = 0;

  const auto start = std::chrono::steady_clock::now();
  for (int c = 0; c < s.chunks; ++c) {
    const long begin = s.steps * c / s.chunks, end = s.steps * (c + 1) / s.chunks;
    for (long k = begin; k < end; ++k) {
      const auto& reading = hw.sample();
      Command u;
      if constexpr (plant::runtime::kPresent<Controller>)
        u = controller.step(reading.force);
      else
        u.setZero();
      hw.apply(u);
      sum_z2 += hw.frame_acceleration().cwiseAbs2();
      sum_u2 += u.cwiseAbs2();
      if (s.log_every > 0 && k % s.log_every == 0) {
        auto line = r.log.row(row++);
        line(0) = static_cast<double>(k) * s.dt;
        line.template segment<NW>(1) = hw.floor_acceleration().transpose();
        line.template segment<NZ>(1 + NW) = hw.frame_acceleration().transpose();
        line.template segment<NZ>(1 + NW + NZ) = reading.accel.transpose();
        line.template segment<NC>(1 + NW + 2 * NZ) = reading.force.transpose();
        line.template segment<NC>(1 + NW + 2 * NZ + NC) = u.transpose();
      }
    }
    if (progress) progress(end, s.steps);
  }
  r.loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double n = static_cast<double>(std::max(s.steps, 1L));
  r.rms_performance = (sum_z2 / n).cwiseSqrt();
  r.rms_command = (sum_u2 / n).cwiseSqrt();
  return r;
}

}  // namespace flexloop::sim
