// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/plant_loop.hpp"

#include <cmath>
#include <string>

#include "online/loop/latency_json.hpp"
#include "online/loop/plant_loop_run.hpp"
#include "online/loop/private_network.hpp"
#include "online/loop/stop_signal.hpp"

namespace flexloop::loop {

PlantLoopResult run_plant_loop(const LoopOptions& o, const artefact::LoopArtefact& loop) {
  // Multicast only in the private namespace; iceoryx sends nothing on any network.
  if (o.transport == rt::TransportKind::kLcm) require_private_network("flexloop plant", o.link);
  const std::string url = loop_lcm_url(o.url, o.link);
  install_stop_handlers();
  PlantLoopResult r;
  // A loop with a compiled fast path runs on it; every other one on the general path, sized at
  // start-up.
  if (!detail::run_plant_compiled(loop, o, url, r)) detail::run_plant_general(loop, o, url, r);
  if (r.divergence.happened())
    r.divergence_message =
        "plant: the loop " + plant::runtime::describe(r.divergence, loop.channels);
  return r;
}

nlohmann::json physical_json(const PhysicalResults& p) {
  const auto channels = [](const std::vector<artefact::Channel>& c, const Eigen::VectorXd& rms) {
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t i = 0; i < c.size() && static_cast<Eigen::Index>(i) < rms.size(); ++i)
      out.push_back(
          {{"name", c[i].name}, {"unit", c[i].unit}, {"rms", rms(static_cast<Eigen::Index>(i))}});
    return out;
  };
  return {{"performance", channels(p.performance, p.rms_performance)},
          {"command", channels(p.actuators, p.rms_command)},
          {"saturated_share", p.saturated_share},
          {"command_limit", std::isfinite(p.command_limit) ? nlohmann::json(p.command_limit)
                                                           : nlohmann::json(nullptr)}};
}

namespace {

nlohmann::json segments_json(const std::vector<SegmentFigures>& segments) {
  nlohmann::json out = nlohmann::json::array();
  for (const SegmentFigures& s : segments)
    out.push_back({{"periods", s.periods},
                   {"cycles", s.cycles},
                   {"deadline_misses", s.deadline_misses},
                   {"answers", s.answers},
                   {"round_trip_p99_ns", s.round_trip_p99_ns}});
  return out;
}

}  // namespace

RunVerdict plant_verdict(const PlantLoopResult& r, const LoopOptions& o) {
  RunVerdict v = judge_run(r.end, r.cycles, r.deadline_misses, o.limits);
  if (!r.lcm_log.error.empty()) add_failure(v, r.lcm_log.error);
  if (r.lcm_log.dropped > 0)
    add_failure(v, "the LCM log " + o.lcm_log + " lost " + std::to_string(r.lcm_log.dropped) +
                       " of " + std::to_string(r.lcm_log.recorded + r.lcm_log.dropped) +
                       " messages (its writer was kept off the CPU longer than its ring lasts)");
  return v;
}

nlohmann::json plant_result_json(const PlantLoopResult& r, const LoopOptions& o, bool with_bins) {
  const LoopAccounts& a = r.accounts;
  nlohmann::json j = {
      {"rate_hz", r.rate_hz},
      {"period_ns", static_cast<std::int64_t>(1e9 / r.rate_hz + 0.5)},
      {"wait_mode", rt::to_string(o.wait)},
      // Who reads the socket is LCM's question; iceoryx's receiver reads the shared memory.
      {"receive_path", o.transport == rt::TransportKind::kIceoryx ? "shared memory"
                                                                  : rt::to_string(o.receive_path)},
      {"spin_margin_ns", r.spin_margin_ns},
      {"cycles", r.cycles},
      {"samples", r.samples},
      {"periods", r.periods},
      {"deadline_misses", r.deadline_misses},
      {"late_answers", r.late_answers},
      {"overruns", r.overruns},
      {"skipped_periods", r.skipped_periods},
      {"safe_command_cycles", r.safe_command_cycles},
      {"safe_after", o.safe_after},
      {"safe_ramp_s", o.safe_ramp_s},
      {"start", o.start == sim::StartKind::kRest ? "rest" : "stationary"},
      {"unapplied_answers", r.unapplied.to_json()},
      {"dropped_messages", drops_json(r.drops)},
      {"round_trip_ns", summary_json(*a.round_trip)},
      {"wakeup_lateness_ns", summary_json(*a.wakeup_lateness)},
      {"plant_compute_ns", summary_json(*a.plant_compute)},
      {"controller_compute_ns", summary_json(*a.controller_compute)},
      {"stats_published", r.stats_published},
      {"publish_failures", r.publish_failures},
      {"cpu", o.realtime.cpu},
      {"fifo", r.fifo},
      {"transport", rt::to_string(o.transport)},
      {"plant_setup", r.setup},
      {"divergence",
       r.divergence.happened() ? nlohmann::json(r.divergence_message) : nlohmann::json(nullptr)},
      {"physical", physical_json(r.physical)},
      {"partial", r.end != RunEnd::kDuration},
      {"segments", segments_json(r.segments)},
      {"lcm_log", o.lcm_log.empty() ? nlohmann::json(nullptr)
                                    : nlohmann::json{{"path", o.lcm_log},
                                                     {"messages", r.lcm_log.recorded},
                                                     {"dropped", r.lcm_log.dropped}}},
      {"verdict", verdict_json(plant_verdict(r, o), r.end, o.limits)}};
  if (with_bins)
    j["histograms"] = {{"round_trip_ns", bins_json(*a.round_trip)},
                       {"wakeup_lateness_ns", bins_json(*a.wakeup_lateness)}};
  return j;
}

}  // namespace flexloop::loop
