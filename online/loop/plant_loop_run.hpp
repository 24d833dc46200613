// SPDX-License-Identifier: BSD-3-Clause
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
#include "online/loop/station_start.hpp"
#include "online/loop/stop_signal.hpp"
#include "online/sim/loop_hardware.hpp"
#include "plant/runtime/divergence.hpp"
#include "plant/runtime/plant_from_artefact.hpp"
#include "rt/event_log_recorder.hpp"
#include "rt/loop_process_setup.hpp"
#include "rt/monotonic_time.hpp"

namespace flexloop::loop::detail {

/// The plant loop of one run in three parts:
///   configure (the constructor)  the start's draw, the station, the log, LCM, the process's
///                                real-time set-up: everything that allocates, opens or throws
///   run()                        the periods, cycle() after cycle(), with the segments' pauses
///                                between them
///   collect()                    the run's figures into the result
template <class Hardware>
class PlantLoopRun {
 public:
  PlantLoopRun(Hardware hw, const artefact::LoopArtefact& loop, const LoopOptions& o,
               const std::string& url, PlantLoopResult& r)
      : loop_(loop),
        o_(o),
        r_(r),
        clock_options_{.period_ns = static_cast<std::int64_t>(1e9 / loop.rate_hz + 0.5),
                       .wait_mode = o.wait,
                       .spin_margin_ns = o.spin_margin_ns},
        clock_(clock_options_),
        duration_s_(o.duration_s > 0 ? o.duration_s : loop.duration_s),
        periods_(static_cast<std::int64_t>(duration_s_ * loop.rate_hz + 0.5)),
        station_(make_station(std::move(hw))),
        recorder_(make_recorder(loop, o)),
        transport_(make_transport(url)),
        sensor_(*transport_, o.channels.sensor),
        stats_(*transport_, o.channels.stats, loop.rate_hz, o.status),
        receive_(rt::receive_mode_for(o.wait)),
        segments_(std::max(1, o.segments)),
        // The overrun policy (online/loop/run_verdict.hpp): 0 = go on whatever misses.
        miss_stop_(o.limits.stop_after_misses > 0 ? o.limits.stop_after_misses
                                                  : std::numeric_limits<std::int64_t>::max()) {
    if (o.status != nullptr) o.status->periods_planned.store(periods_, std::memory_order_relaxed);
    r.rate_hz = loop.rate_hz;
    r.spin_margin_ns = rt::effective_spin_margin_ns(clock_options_);
    const rt::LoopProcessSetup setup = rt::set_up_loop_process(*transport_, o.realtime);
    r.fifo = setup.fifo;
    r.setup = setup.text + (dma_.active() ? "  ok    " : "  WARN  ") + dma_.message() + "\n" +
              wait_for_controller();
    r.segments.reserve(static_cast<std::size_t>(segments_));
    if (!o.quiet)
      std::printf(
          "plant: %s, %.6g Hz for %.6g s (%lld periods), wait %s, %s\nstart: %s\n%s",
          loop.name.c_str(), loop.rate_hz, duration_s_, static_cast<long long>(periods_),
          rt::to_string(o.wait), transport_->describe().c_str(),
          sim::describe_start(o.start, sim::run_start(loop), sim::run_loop_name(loop)).c_str(),
          r.setup.c_str());
    std::fflush(stdout);
  }

  /// The periods until the duration, a stop, the miss limit or a divergence (r.end says which).
  void run() {
    clock_.start();
    stats_.start(rt::monotonic_now_ns());
    r_.end = RunEnd::kDuration;
    while (clock_.schedule().periods_elapsed() < periods_) {
      if (stop_requested()) {
        r_.end = RunEnd::kInterrupted;
        break;
      }
      if (station_->deadline_misses() >= miss_stop_) {
        r_.end = RunEnd::kMissLimit;
        break;
      }
      if (static_cast<std::int64_t>(r_.segments.size()) + 1 < segments_ &&
          clock_.schedule().periods_elapsed() >=
              periods_ * static_cast<std::int64_t>(r_.segments.size() + 1) / segments_) {
        // The last sample had its window (the receive above ran to its answer or the deadline):
        // an answer that comes during the pause stays unread, and so counts as a miss.
        close_segment();
        if (o_.between_segments) o_.between_segments();
        clock_.resume();
        continue;  // the stop and miss checks again, after the pause
      }
      if (!cycle()) {
        r_.divergence = plant::runtime::locate_divergence(
            samples_, 1.0 / loop_.rate_hz, station_->hardware().performance(), station_->command());
        r_.end = RunEnd::kDivergence;
        break;
      }
    }
    // The last sample's answer had its window too.
    settle(clock_.next_deadline_ns());
    close_segment();
  }

  void collect() {
    const rt::DeadlineSchedule& s = clock_.schedule();
    r_.periods = s.periods_elapsed();
    r_.cycles = s.cycles();
    r_.samples = station_->last_sample().seq;
    r_.overruns = s.overruns();
    r_.skipped_periods = s.skipped_periods();
    r_.deadline_misses = station_->deadline_misses();
    r_.late_answers = station_->late_answers();
    r_.safe_command_cycles = station_->safe_command_cycles();
    r_.drops = station_->commands().drops();
    r_.stats_published = stats_.published();
    r_.publish_failures = sensor_.failures();
    r_.physical.performance = loop_.channels.performance;
    r_.physical.actuators = loop_.channels.actuators;
    r_.physical.rms_performance = station_->rms_performance();
    r_.physical.rms_command = station_->rms_command();
    r_.physical.saturated_share = station_->saturated_share();
    if (recorder_) {
      r_.lcm_log.error = recorder_->finish();
      r_.lcm_log.recorded = recorder_->recorded();
      r_.lcm_log.dropped = recorder_->dropped();
    }
  }

 private:
  /// One period: wait for its deadline, apply the command the last answer settles, sample and
  /// publish, wait for the answer. No allocation or exception, and no lock but LCM's own queue's
  /// on its receive-thread path (rt/lcm_transport.hpp) or iceoryx's uncontended one in publish.
  /// False: the plant's outputs left the finite range (a divergence; nothing published).
  bool cycle() noexcept {
    LoopAccounts& a = r_.accounts;
    const rt::CycleStart c = clock_.wait_next();
    a.wakeup_lateness->record(c.lateness_ns);
    const std::int64_t t0 = rt::monotonic_now_ns();
    settle(c.due_ns);
    const auto& sample = station_->sample(t0);
    // The plant's outputs with the command its actuators hold (the answer to the previous
    // sample): sim checks the same outputs with the command that answers them, so a divergence
    // driven by the command can show one sample apart.
    if (plant::runtime::beyond_range(station_->hardware().performance(), station_->command()))
      return false;
    ++samples_;
    published_ns_ = rt::monotonic_now_ns();
    a.plant_compute->record(published_ns_ - t0);
    sensor_.publish(sample);
    // Waiting for the answer (hybrid): spin from the publication on while the controller
    // answers. Once safe_after samples in a row went unanswered (nobody answers: the plant alone,
    // or a controller that stopped), sleep until the clock's own spin window before the deadline
    // instead: spinning whole periods at SCHED_FIFO uses up the kernel's RT bandwidth
    // (sched_rt_runtime_us, 95 % of each second) and the loop is then throttled for the rest of
    // the second (the plant alone at 10 kHz for 2 s: one wake-up 48.4 ms late, 488 periods
    // skipped). The first answer brings the spinning back (the miss count resets).
    const std::int64_t spin_from =
        station_->consecutive_misses() < station_->settings().safe_after
            ? published_ns_
            : std::max(published_ns_, clock_.next_deadline_ns() - r_.spin_margin_ns);
    transport_->handle_until(
        clock_.next_deadline_ns(), receive_, [this] { return station_->answered(); }, spin_from);
    const LoopCounts counts{clock_.schedule().cycles(), station_->deadline_misses(),
                            clock_.schedule().overruns(), station_->commands().drops().total(),
                            station_->safe_command_cycles()};
    stats_.poll(rt::monotonic_now_ns(), a, counts);
    return true;
  }

  // Settles the last period; an answer it did not apply (held or safe) is recorded by its
  // sample's seq, for hil's replay of the run (online/loop/sample_ranges.hpp).
  void settle(std::int64_t due_ns) noexcept {
    const std::int64_t seq = station_->last_sample().seq;
    const CommandSource source = station_->settle(due_ns);
    if (source == CommandSource::kHeld || source == CommandSource::kSafe) r_.unapplied.add(seq);
    record_answer();
  }

  void record_answer() noexcept {
    if (const auto* answer = station_->last_answer()) {
      LoopAccounts& a = r_.accounts;
      const std::int64_t round_trip = station_->commands().newest_received_ns() - published_ns_;
      a.round_trip->record(round_trip);
      a.segment_round_trip->record(round_trip);
      a.controller_compute->record(answer->controller_compute_ns);
    }
  }

  // Segments (LoopOptions::segments): segment k ends once the grid covered periods (k+1)/K.
  void close_segment() {
    SegmentFigures s;
    s.periods = clock_.schedule().periods_elapsed() - total_.periods;
    s.cycles = clock_.schedule().cycles() - total_.cycles;
    s.deadline_misses = station_->deadline_misses() - total_.deadline_misses;
    LoopAccounts& a = r_.accounts;
    s.answers = a.segment_round_trip->count();
    s.round_trip_p99_ns = s.answers > 0 ? a.segment_round_trip->percentile(0.99) : 0;
    a.segment_round_trip->reset();
    total_.periods += s.periods;
    total_.cycles += s.cycles;
    total_.deadline_misses += s.deadline_misses;
    r_.segments.push_back(s);
  }

  // The station at the run's start: the start the controller process draws as well
  // (online/loop/station_start.hpp), or rest.
  std::unique_ptr<PlantStation<Hardware>> make_station(Hardware hw) {
    const std::optional<sim::DrawnStart> start = start_plant_hardware(loop_, o_.start, hw);
    // A new epoch per run: the controller sees a restart, old answers are stale.
    const std::int64_t epoch = rt::monotonic_now_ns() ^ (static_cast<std::int64_t>(getpid()) << 40);
    const PlantStationSettings settings = plant_station_settings(loop_, o_, epoch);
    r_.physical.command_limit = settings.command_limit;
    auto station = std::make_unique<PlantStation<Hardware>>(std::move(hw), settings);
    if (start) station->start_command(typename Hardware::Command(start->last_command));
    return station;
  }

  // The log (before the subscription and the publishers, which record into it): about a second
  // of the loop's traffic in its ring, the channel map first. Null: no log asked for.
  static std::unique_ptr<rt::EventLogRecorder> make_recorder(const artefact::LoopArtefact& loop,
                                                             const LoopOptions& o) {
    if (o.lcm_log.empty()) return nullptr;
    const std::string map = channel_map_json(loop).dump();
    const int largest = std::max({rt::max_encoded_size<flexloop_msgs::sensor_sample_t>(),
                                  rt::max_encoded_size<flexloop_msgs::actuator_command_t>(),
                                  rt::max_encoded_size<flexloop_msgs::loop_stats_t>(),
                                  static_cast<int>(map.size())});
    auto recorder = std::make_unique<rt::EventLogRecorder>(
        o.lcm_log, largest, static_cast<int>(2 * loop.rate_hz) + 1024);
    recorder->record(recorder->channel(kChannelMapChannel), map.data(),
                     static_cast<int>(map.size()), rt::monotonic_now_ns());
    return recorder;
  }

  // The carrier, recording into the log and delivering answers to the station: wired before the
  // publishers, which take the recorder when they are made.
  std::unique_ptr<rt::LoopTransport> make_transport(const std::string& url) {
    auto t = std::make_unique<rt::LoopTransport>(
        rt::LoopTransportOptions{.kind = o_.transport,
                                 .url = url,
                                 .receive_path = o_.receive_path,
                                 .runtime_name = "plant"});
    t->record_to(recorder_.get());
    t->subscribe(o_.channels.command, station_->commands());
    return t;
  }

  // Over iceoryx the first samples would go nowhere until RouDi has connected the controller's
  // subscription and its answer (LCM has no connections): wait for both, at most
  // connect_timeout_s. The set-up line says how long it took, or that nobody came.
  std::string wait_for_controller() {
    if (o_.transport != rt::TransportKind::kIceoryx || o_.connect_timeout_s <= 0) return "";
    const std::int64_t took = rt::wait_until_connected(
        [this] { return sensor_.has_subscribers() && transport_->subscriptions_connected(); },
        static_cast<std::int64_t>(o_.connect_timeout_s * 1e9));
    char text[160];
    if (took >= 0)
      std::snprintf(text, sizeof text, "  ok    iceoryx: the controller connected after %.1f ms\n",
                    took / 1e6);
    else
      std::snprintf(text, sizeof text,
                    "  WARN  iceoryx: no controller connected within %.3g s; the plant runs on\n",
                    o_.connect_timeout_s);
    return text;
  }

  const artefact::LoopArtefact& loop_;
  const LoopOptions& o_;
  PlantLoopResult& r_;
  rt::PeriodicClockOptions clock_options_;
  rt::PeriodicClock clock_;
  double duration_s_;
  std::int64_t periods_;
  std::unique_ptr<PlantStation<Hardware>> station_;
  std::unique_ptr<rt::EventLogRecorder> recorder_;
  std::unique_ptr<rt::LoopTransport> transport_;
  rt::LoopPublisher<flexloop_msgs::sensor_sample_t> sensor_;
  StatsPublisher stats_;
  const rt::CpuDmaLatencyHold dma_;
  rt::ReceiveMode receive_;
  std::int64_t segments_, miss_stop_;
  std::int64_t published_ns_ = 0;
  long samples_ = 0;
  SegmentFigures total_;  // the counts when the current segment began
};

template <class Hardware>
void run_plant_with(Hardware hw, const artefact::LoopArtefact& loop, const LoopOptions& o,
                    const std::string& url, PlantLoopResult& r) {
  PlantLoopRun<Hardware> run(std::move(hw), loop, o, url, r);
  run.run();
  run.collect();
}

/// The loop on the fixed-size kernels of the compiled loop that matches the artefact
/// (plant/runtime/compiled_loops.hpp), with its hardware effects: false when none matches.
bool run_plant_compiled(const artefact::LoopArtefact&, const LoopOptions&, const std::string&,
                        PlantLoopResult&);
void run_plant_general(const artefact::LoopArtefact&, const LoopOptions&, const std::string&,
                       PlantLoopResult&);  // any size, sized at start-up

}  // namespace flexloop::loop::detail
