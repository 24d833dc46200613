#include "tools/hil/plant_loop.hpp"

#include <unistd.h>

#include <cstdio>

#include "rt/loop_process_setup.hpp"
#include "rt/monotonic_time.hpp"
#include "tools/hil/latency_json.hpp"
#include "tools/hil/loop_scene.hpp"
#include "tools/hil/private_network.hpp"
#include "tools/hil/stop_signal.hpp"

namespace flexloop::hil {

namespace {

template <class Plant>
void run_with(const Plant& plant, const LoopScene& scene, const LoopOptions& o,
              const std::string& url, PlantLoopResult& r) {
  const rt::PeriodicClockOptions clock_options{
      .period_ns = static_cast<std::int64_t>(1e9 / scene.rate_hz + 0.5),
      .wait_mode = o.wait,
      .spin_margin_ns = o.spin_margin_ns};
  rt::PeriodicClock clock(clock_options);
  const double duration_s = o.duration_s > 0 ? o.duration_s : scene.scene.run.duration_s;
  const auto periods = static_cast<std::int64_t>(duration_s * scene.rate_hz + 0.5);
  // A new epoch per run: the controller sees a restart, old answers are stale.
  const std::int64_t epoch = rt::monotonic_now_ns() ^ (static_cast<std::int64_t>(getpid()) << 40);
  auto station = std::make_unique<PlantStation<Plant>>(
      plant, PlantStationSettings{.floor_rms_mps2 = scene.scene.floor.rms_mps2,
                                  .seed = scene.scene.floor.seed,
                                  .safe_after = o.safe_after,
                                  .epoch = epoch,
                                  .period_ns = clock_options.period_ns});
  rt::LcmTransport lcm(url);
  lcm.subscribe(o.channels.command, station->commands());
  rt::LcmPublisher<flexloop_msgs::sensor_sample_t> sensor(lcm, o.channels.sensor);
  StatsPublisher stats(lcm, o.channels.stats, scene.rate_hz);
  const rt::CpuDmaLatencyHold dma;
  r.rate_hz = scene.rate_hz;
  const rt::LoopProcessSetup setup = rt::set_up_loop_process(lcm, o.realtime);
  r.fifo = setup.fifo;
  r.setup = setup.text + (dma.active() ? "  ok    " : "  WARN  ") + dma.message() + "\n";
  if (!o.quiet)
    std::printf("plant: %s, %.6g Hz for %.6g s (%lld periods), wait %s, LCM %s\n%s",
                scene.scene.name.c_str(), scene.rate_hz, duration_s,
                static_cast<long long>(periods), rt::to_string(o.wait), url.c_str(),
                r.setup.c_str());
  std::fflush(stdout);

  LoopAccounts& a = r.accounts;
  const rt::ReceiveMode receive = rt::receive_mode_for(o.wait);
  const auto answered = [&] { return station->answered(); };
  std::int64_t published_ns = 0;
  LoopCounts counts;
  clock.start();
  stats.start(rt::monotonic_now_ns());
  while (clock.schedule().periods_elapsed() < periods && !stop_requested()) {
    const rt::CycleStart c = clock.wait_next();
    a.wakeup_lateness->record(c.lateness_ns);
    const std::int64_t t0 = rt::monotonic_now_ns();
    station->settle(c.due_ns);
    if (const auto* answer = station->last_answer()) {
      a.round_trip->record(station->commands().newest_received_ns() - published_ns);
      a.controller_compute->record(answer->controller_compute_ns);
    }
    const auto& sample = station->sample(t0);
    published_ns = rt::monotonic_now_ns();
    a.plant_compute->record(published_ns - t0);
    sensor.publish(sample);
    lcm.handle_until(clock.next_deadline_ns(), receive, answered, published_ns);
    counts = {clock.schedule().cycles(), station->deadline_misses(), clock.schedule().overruns(),
              station->commands().drops().total(), station->safe_command_cycles()};
    stats.poll(rt::monotonic_now_ns(), a, counts);
  }
  // The last sample's answer had its window too.
  station->settle(clock.next_deadline_ns());
  if (const auto* answer = station->last_answer()) {
    a.round_trip->record(station->commands().newest_received_ns() - published_ns);
    a.controller_compute->record(answer->controller_compute_ns);
  }
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
}

}  // namespace

PlantLoopResult run_plant_loop(const LoopOptions& o) {
  require_private_network("flexloop plant", o.link);
  return run_plant_loop(o, load_loop_scene(o.scene_path, o.rate_hz));
}

PlantLoopResult run_plant_loop(const LoopOptions& o, const LoopScene& scene) {
  require_private_network("flexloop plant", o.link);
  const std::string url = loop_lcm_url(o.url, o.link);
  install_stop_handlers();
  PlantLoopResult r;
  with_loop_plant(scene, [&](const auto& plant) { run_with(plant, scene, o, url, r); });
  return r;
}

nlohmann::json plant_result_json(const PlantLoopResult& r, const LoopOptions& o, bool with_bins) {
  const LoopAccounts& a = r.accounts;
  nlohmann::json j = {{"rate_hz", r.rate_hz},
                      {"period_ns", static_cast<std::int64_t>(1e9 / r.rate_hz + 0.5)},
                      {"wait_mode", rt::to_string(o.wait)},
                      {"cycles", r.cycles},
                      {"periods", r.periods},
                      {"deadline_misses", r.deadline_misses},
                      {"late_answers", r.late_answers},
                      {"overruns", r.overruns},
                      {"skipped_periods", r.skipped_periods},
                      {"safe_command_cycles", r.safe_command_cycles},
                      {"safe_after", o.safe_after},
                      {"dropped_messages", drops_json(r.drops)},
                      {"round_trip_ns", summary_json(*a.round_trip)},
                      {"wakeup_lateness_ns", summary_json(*a.wakeup_lateness)},
                      {"plant_compute_ns", summary_json(*a.plant_compute)},
                      {"controller_compute_ns", summary_json(*a.controller_compute)},
                      {"stats_published", r.stats_published},
                      {"publish_failures", r.publish_failures},
                      {"cpu", o.realtime.cpu},
                      {"fifo", r.fifo},
                      {"plant_setup", r.setup}};
  if (with_bins)
    j["histograms"] = {{"round_trip_ns", bins_json(*a.round_trip)},
                       {"wakeup_lateness_ns", bins_json(*a.wakeup_lateness)}};
  return j;
}

}  // namespace flexloop::hil
