#pragma once
// The plant loop's body (online/loop/plant_loop.hpp) for one composed hardware type, and its
// instantiations with the artefact's effects (online/sim/loop_hardware.hpp): the compiled loops
// (plant_loop_compiled.cpp) and the general path (plant_loop_general.cpp), in separate
// translation units so that they compile in parallel.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "online/loop/channel_map.hpp"
#include "online/loop/plant_loop.hpp"
#include "online/loop/plant_station.hpp"
#include "online/loop/stop_signal.hpp"
#include "online/sim/loop_hardware.hpp"
#include "plant/runtime/divergence.hpp"
#include "rt/event_log_recorder.hpp"
#include "rt/loop_process_setup.hpp"
#include "rt/monotonic_time.hpp"

namespace flexloop::hil::detail {

template <class Hardware>
void run_plant_with(Hardware hw, const artefact::LoopArtefact& loop, const LoopOptions& o,
                    const std::string& url, PlantLoopResult& r) {
  const rt::PeriodicClockOptions clock_options{
      .period_ns = static_cast<std::int64_t>(1e9 / loop.rate_hz + 0.5),
      .wait_mode = o.wait,
      .spin_margin_ns = o.spin_margin_ns};
  rt::PeriodicClock clock(clock_options);
  const double duration_s = o.duration_s > 0 ? o.duration_s : loop.duration_s;
  const auto periods = static_cast<std::int64_t>(duration_s * loop.rate_hz + 0.5);
  // A new epoch per run: the controller sees a restart, old answers are stale.
  const std::int64_t epoch = rt::monotonic_now_ns() ^ (static_cast<std::int64_t>(getpid()) << 40);
  const auto& actuator = loop.effects.actuator;
  r.physical.command_limit = actuator.present ? actuator.force_limit_n / std::abs(actuator.gain)
                                              : std::numeric_limits<double>::infinity();
  // The start the controller process draws as well (online/sim/loop_start.hpp).
  const auto& stationary = sim::run_start(loop);
  std::optional<sim::DrawnStart> start;
  if (o.start == sim::StartKind::kStationary && stationary.exists()) {
    start = sim::draw_start(loop, stationary, sim::floor_filter_states(hw));
    sim::start_hardware_at(loop, *start, hw);
  }
  auto station = std::make_unique<PlantStation<Hardware>>(
      std::move(hw), PlantStationSettings{.safe_after = o.safe_after,
                                          .epoch = epoch,
                                          .period_ns = clock_options.period_ns,
                                          .command_limit = r.physical.command_limit,
                                          .safe_ramp_periods = static_cast<std::int64_t>(
                                              o.safe_ramp_s * loop.rate_hz + 0.5)});
  if (start) station->start_command(typename Hardware::Command(start->last_command));
  // The log (before the subscription and the publishers, which record into it): about a second
  // of the loop's traffic in its ring, the channel map first.
  std::unique_ptr<rt::EventLogRecorder> recorder;
  if (!o.lcm_log.empty()) {
    const std::string map = channel_map_json(loop).dump();
    const int largest = std::max({rt::max_encoded_size<flexloop_msgs::sensor_sample_t>(),
                                  rt::max_encoded_size<flexloop_msgs::actuator_command_t>(),
                                  rt::max_encoded_size<flexloop_msgs::loop_stats_t>(),
                                  static_cast<int>(map.size())});
    recorder = std::make_unique<rt::EventLogRecorder>(o.lcm_log, largest,
                                                      static_cast<int>(2 * loop.rate_hz) + 1024);
    recorder->record(recorder->channel(kChannelMapChannel), map.data(),
                     static_cast<int>(map.size()), rt::monotonic_now_ns());
  }
  rt::LcmTransport lcm(url, o.receive_path);
  lcm.record_to(recorder.get());
  lcm.subscribe(o.channels.command, station->commands());
  rt::LcmPublisher<flexloop_msgs::sensor_sample_t> sensor(lcm, o.channels.sensor);
  StatsPublisher stats(lcm, o.channels.stats, loop.rate_hz, o.status);
  if (o.status != nullptr) o.status->periods_planned.store(periods, std::memory_order_relaxed);
  const rt::CpuDmaLatencyHold dma;
  r.rate_hz = loop.rate_hz;
  r.spin_margin_ns = rt::effective_spin_margin_ns(clock_options);
  const rt::LoopProcessSetup setup = rt::set_up_loop_process(lcm, o.realtime);
  r.fifo = setup.fifo;
  r.setup = setup.text + (dma.active() ? "  ok    " : "  WARN  ") + dma.message() + "\n";
  if (!o.quiet)
    std::printf(
        "plant: %s, %.6g Hz for %.6g s (%lld periods), wait %s, LCM %s\nstart: %s\n%s",
        loop.name.c_str(), loop.rate_hz, duration_s, static_cast<long long>(periods),
        rt::to_string(o.wait), url.c_str(),
        sim::describe_start(o.start, sim::run_start(loop), sim::run_loop_name(loop)).c_str(),
        r.setup.c_str());
  std::fflush(stdout);

  LoopAccounts& a = r.accounts;
  const rt::ReceiveMode receive = rt::receive_mode_for(o.wait);
  const auto answered = [&] { return station->answered(); };
  std::int64_t published_ns = 0;
  const auto record_answer = [&] {
    if (const auto* answer = station->last_answer()) {
      const std::int64_t round_trip = station->commands().newest_received_ns() - published_ns;
      a.round_trip->record(round_trip);
      a.segment_round_trip->record(round_trip);
      a.controller_compute->record(answer->controller_compute_ns);
    }
  };
  // Segments (LoopOptions::segments): segment k ends once the grid covered periods (k+1)/K.
  const std::int64_t segments = std::max(1, o.segments);
  r.segments.reserve(static_cast<std::size_t>(segments));
  SegmentFigures total;  // the counts when the current segment began
  const auto close_segment = [&] {
    SegmentFigures s;
    s.periods = clock.schedule().periods_elapsed() - total.periods;
    s.cycles = clock.schedule().cycles() - total.cycles;
    s.deadline_misses = station->deadline_misses() - total.deadline_misses;
    s.answers = a.segment_round_trip->count();
    s.round_trip_p99_ns = s.answers > 0 ? a.segment_round_trip->percentile(0.99) : 0;
    a.segment_round_trip->reset();
    total.periods += s.periods;
    total.cycles += s.cycles;
    total.deadline_misses += s.deadline_misses;
    r.segments.push_back(s);
  };
  LoopCounts counts;
  long samples = 0;
  clock.start();
  stats.start(rt::monotonic_now_ns());
  // The overrun policy (online/loop/run_verdict.hpp): 0 = go on whatever misses.
  const std::int64_t miss_stop = o.limits.stop_after_misses > 0
                                     ? o.limits.stop_after_misses
                                     : std::numeric_limits<std::int64_t>::max();
  r.end = RunEnd::kDuration;
  while (clock.schedule().periods_elapsed() < periods) {
    if (stop_requested()) {
      r.end = RunEnd::kInterrupted;
      break;
    }
    if (station->deadline_misses() >= miss_stop) {
      r.end = RunEnd::kMissLimit;
      break;
    }
    if (static_cast<std::int64_t>(r.segments.size()) + 1 < segments &&
        clock.schedule().periods_elapsed() >=
            periods * static_cast<std::int64_t>(r.segments.size() + 1) / segments) {
      // The last sample had its window (the receive above ran to its answer or the deadline):
      // an answer that comes during the pause stays unread, and so counts as a miss.
      close_segment();
      if (o.between_segments) o.between_segments();
      clock.resume();
      continue;  // the stop and miss checks again, after the pause
    }
    const rt::CycleStart c = clock.wait_next();
    a.wakeup_lateness->record(c.lateness_ns);
    const std::int64_t t0 = rt::monotonic_now_ns();
    station->settle(c.due_ns);
    record_answer();
    const auto& sample = station->sample(t0);
    // The plant's outputs with the command its actuators hold (the answer to the previous
    // sample): sim checks the same outputs with the command that answers them, so a divergence
    // driven by the command can show one sample apart.
    if (plant::runtime::beyond_range(station->hardware().performance(), station->command())) {
      r.divergence = plant::runtime::locate_divergence(
          samples, 1.0 / loop.rate_hz, station->hardware().performance(), station->command());
      r.end = RunEnd::kDivergence;
      break;
    }
    ++samples;
    published_ns = rt::monotonic_now_ns();
    a.plant_compute->record(published_ns - t0);
    sensor.publish(sample);
    // Waiting for the answer (hybrid): spin from the publication on while the controller
    // answers. Once safe_after samples in a row went unanswered (nobody answers: the plant alone,
    // or a controller that stopped), sleep until the clock's own spin window before the deadline
    // instead: spinning whole periods at SCHED_FIFO uses up the kernel's RT bandwidth
    // (sched_rt_runtime_us, 95 % of each second) and the loop is then throttled for the rest of
    // the second (measured before: the plant alone at 10 kHz for 2 s, one wake-up 48.4 ms late,
    // 488 periods skipped). The first answer brings the spinning back (the miss count resets).
    const std::int64_t spin_from =
        station->consecutive_misses() < station->settings().safe_after
            ? published_ns
            : std::max(published_ns, clock.next_deadline_ns() - r.spin_margin_ns);
    lcm.handle_until(clock.next_deadline_ns(), receive, answered, spin_from);
    counts = {clock.schedule().cycles(), station->deadline_misses(), clock.schedule().overruns(),
              station->commands().drops().total(), station->safe_command_cycles()};
    stats.poll(rt::monotonic_now_ns(), a, counts);
  }
  // The last sample's answer had its window too.
  station->settle(clock.next_deadline_ns());
  record_answer();
  close_segment();
  const rt::DeadlineSchedule& s = clock.schedule();
  r.periods = s.periods_elapsed();
  r.cycles = s.cycles();
  r.overruns = s.overruns();
  r.skipped_periods = s.skipped_periods();
  r.deadline_misses = station->deadline_misses();
  r.late_answers = station->late_answers();
  r.safe_command_cycles = station->safe_command_cycles();
  r.drops = station->commands().drops();
  r.stats_published = stats.published();
  r.publish_failures = sensor.failures();
  r.physical.performance = loop.channels.performance;
  r.physical.actuators = loop.channels.actuators;
  r.physical.rms_performance = station->rms_performance();
  r.physical.rms_command = station->rms_command();
  r.physical.saturated_share = station->saturated_share();
  if (recorder) {
    r.lcm_log.error = recorder->finish();
    r.lcm_log.recorded = recorder->recorded();
    r.lcm_log.dropped = recorder->dropped();
  }
}

/// The loop on the fixed-size kernels of the compiled loop that matches the artefact
/// (plant/runtime/compiled_loops.hpp), with its hardware effects: false when none matches.
bool run_plant_compiled(const artefact::LoopArtefact&, const LoopOptions&, const std::string&,
                        PlantLoopResult&);
void run_plant_general(const artefact::LoopArtefact&, const LoopOptions&, const std::string&,
                       PlantLoopResult&);  // any size, sized at start-up

}  // namespace flexloop::hil::detail
