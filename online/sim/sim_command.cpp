// SPDX-License-Identifier: BSD-3-Clause
#include "online/sim/sim_command.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "plant/runtime/divergence.hpp"

namespace flexloop::sim {

bool logs_controller_on(const artefact::LoopArtefact& a, const SimRequest& r) {
  return a.controller != artefact::ControllerKind::kNone && r.controller_on;
}

RunSettings sim_settings(const artefact::LoopArtefact& a, long log_every) {
  RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(a.duration_s / s.dt);
  s.log_every = log_every;
  return s;
}

BothRuns run_sim(const artefact::LoopArtefact& a, const SimRequest& r) {
  const bool on = logs_controller_on(a, r);
  return run_artefact(a, sim_settings(a, r.log_every),
                      {.general = r.general,
                       .start = r.start,
                       .log_off = r.log_both || (r.log && !on),
                       .log_on = r.log_both || (r.log && on),
                       .progress = r.progress,
                       .on_first = on,
                       .after_first_run = r.after_first_run});
}

namespace {

// A run that left the stated range (online/sim/closed_loop_run.hpp): what, when and where.
void require_bounded_run(const artefact::LoopArtefact& a, const RunResult& r, const char* run) {
  const Divergence& d = r.divergence;
  if (!d.happened()) return;
  throw std::runtime_error("the loop with the controller " + std::string(run) + " " +
                           plant::runtime::describe(d, a.channels) + "; nothing written");
}

}  // namespace

void require_completed(const artefact::LoopArtefact& a, const BothRuns& r) {
  if (r.controlled && !r.on.controller.failure.empty())
    throw std::runtime_error(a.fmu.file + ": " + r.on.controller.failure +
                             "; the controller-on run answered with the safe command from there "
                             "on; nothing written");
  require_bounded_run(a, r.off, "off");
  if (r.controlled) require_bounded_run(a, r.on, "on");
}

std::vector<std::string> log_header(const artefact::LoopArtefact& a) {
  std::vector<std::string> h{"t_s"};
  const auto add = [&h](const char* role, const std::vector<artefact::Channel>& channels) {
    for (const auto& c : channels)
      h.push_back(std::string(role) + " " + c.name + " [" + c.unit + "]");
  };
  add("disturbance", a.channels.disturbances);
  add("performance", a.channels.performance);
  add("performance sensor", a.channels.performance);
  add("sensor", a.channels.sensors);
  add("command", a.channels.actuators);
  return h;
}

std::vector<RmsRow> rms_table(const artefact::LoopArtefact& a, const BothRuns& r) {
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::vector<RmsRow> rows;
  for (Eigen::Index i = 0; i < r.off.rms_performance.size(); ++i) {
    const auto& c = a.channels.performance[static_cast<std::size_t>(i)];
    const double off = r.off.rms_performance(i);
    const double on = r.controlled ? r.on.rms_performance(i) : kNone;
    rows.push_back({c.name, c.unit, off, on, r.controlled ? 20 * std::log10(on / off) : kNone});
  }
  return rows;
}

}  // namespace flexloop::sim
