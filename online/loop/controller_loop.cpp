// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/controller_loop.hpp"

#include <cstdio>

#include "online/loop/controller_station.hpp"
#include "online/loop/latency_json.hpp"
#include "online/loop/loop_controller.hpp"
#include "online/loop/private_network.hpp"
#include "online/loop/station_start.hpp"
#include "online/loop/stop_signal.hpp"
#include "online/sim/loop_hardware.hpp"
#include "rt/loop_transport.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/thread_allocations.hpp"

namespace flexloop::loop {

namespace {

// The cycle: one sample's answer, timed, its allocations counted, published, accounted. No
// allocation, lock or exception (ControllerStation::answer, LoopPublisher::publish,
// LatencyHistogram::record); a controller that allocates is counted, not stopped.
template <class Controller>
void answer_sample(ControllerStation<Controller>& station, const flexloop_msgs::sensor_sample_t& s,
                   rt::LoopPublisher<flexloop_msgs::actuator_command_t>& command,
                   ControllerLoopResult& r, LoopStatus* status) noexcept {
  // For a watcher (hil): the sample being answered, so that a crash in the step is placed.
  if (status) status->controller_sample.store(s.seq, std::memory_order_relaxed);
  const std::uint64_t a0 = rt::thread_allocations();
  const std::int64_t t0 = rt::monotonic_now_ns();
  flexloop_msgs::actuator_command_t& cmd = station.answer(s);
  const std::int64_t t1 = rt::monotonic_now_ns();
  if (const std::uint64_t made = rt::thread_allocations() - a0; made > 0) {
    r.allocations += static_cast<std::int64_t>(made);
    ++r.answers_allocating;
  }
  cmd.controller_compute_ns = t1 - t0;
  cmd.t_ns = t1;
  command.publish(cmd);
  r.compute->record(t1 - t0);
  r.response->record(rt::monotonic_now_ns() - station.samples().newest_received_ns());
}

// The samples before `s` that went unanswered, for hil's replay of the run
// (online/loop/sample_ranges.hpp). A second plant run makes the record incomplete.
void record_unanswered(const flexloop_msgs::sensor_sample_t& s, std::int64_t& epoch,
                       std::int64_t& last_seq, SampleRanges& unanswered) noexcept {
  if (last_seq >= 0 && s.plant_epoch != epoch) unanswered.mark_incomplete();
  if (last_seq < 0 || s.plant_epoch != epoch) last_seq = 0;
  epoch = s.plant_epoch;
  unanswered.add(last_seq + 1, s.seq - 1);
  last_seq = s.seq;
}

// What the controller said of its run (a controller FMU's failure, warnings and log; nothing for
// flexloop's own kernels): into the result, its log to stderr.
void take_report(const controller::runtime::ControllerReport& c, ControllerLoopResult& r) {
  r.controller_failure = c.failure;
  r.controller_warnings = c.warnings;
  r.first_warning = c.first_warning;
  r.controller_messages = static_cast<std::int64_t>(c.messages.size());
  r.controller_messages_lost = c.messages_lost;
  for (const std::string& m : c.messages) std::fprintf(stderr, "%s\n", m.c_str());
  if (c.messages_lost > 0)
    std::fprintf(stderr, "(%ld more messages of the controller did not fit its log ring)\n",
                 c.messages_lost);
}

template <class Controller>
ControllerLoopResult run_with(Controller controller, const LoopOptions& o,
                              const artefact::LoopArtefact& loop,
                              const std::function<void()>& ready) {
  const std::string url = loop_lcm_url(o.url, o.link);
  const auto period_ns = static_cast<std::int64_t>(1e9 / loop.rate_hz + 0.5);
  const std::int64_t spin_margin_ns = rt::effective_spin_margin_ns(
      {.period_ns = period_ns, .wait_mode = o.wait, .spin_margin_ns = o.spin_margin_ns});
  install_stop_handlers();

  ControllerLoopResult r;
  r.period_ns = period_ns;
  r.allocations_counted = rt::allocations_counted();
  // The start the plant process draws: the same artefact, the same seeds, the same numbers.
  auto station = std::make_unique<ControllerStation<Controller>>(
      std::move(controller), o.safe_after, controller_start(loop, o.start));
  rt::LoopTransport transport({.kind = o.transport,
                               .url = url,
                               .receive_path = o.receive_path,
                               .runtime_name = "controller"});
  transport.subscribe(o.channels.sensor, station->samples());
  rt::LoopPublisher<flexloop_msgs::actuator_command_t> command(transport, o.channels.command);
  const rt::CpuDmaLatencyHold dma;
  const rt::LoopProcessSetup setup = rt::set_up_loop_process(transport, o.realtime);
  r.fifo = setup.fifo;
  r.setup = setup.text + (dma.active() ? "  ok    " : "  WARN  ") + dma.message() + "\n";
  if (!o.quiet)
    std::printf(
        "controller: %s, %s, %ld sensors -> %ld actuators at %.6g Hz, wait %s, safe after %d "
        "misses, %s\n%s",
        loop.name.c_str(), artefact::to_string(loop.controller).c_str(),
        static_cast<long>(station->controller().sensors()),
        static_cast<long>(station->controller().actuators()), loop.rate_hz, rt::to_string(o.wait),
        o.safe_after, transport.describe().c_str(), r.setup.c_str());
  std::fflush(stdout);
  if (ready) ready();

  const rt::ReceiveMode receive = rt::receive_mode_for(o.wait);
  const std::int64_t end =
      o.duration_s > 0 ? rt::monotonic_now_ns() + static_cast<std::int64_t>(o.duration_s * 1e9)
                       : INT64_MAX;
  const auto wake = [&] { return station->samples().has_fresh() || stop_requested(); };
  constexpr std::int64_t kLookNs = 20'000'000;  // how often an idle loop checks the stop flag
  std::int64_t spin_from = 0;
  std::int64_t epoch = 0, last_seq = -1;  // the plant run answered, and its last sample answered
  while (!stop_requested()) {
    const std::int64_t now = rt::monotonic_now_ns();
    if (now >= end) break;
    transport.handle_until(now + kLookNs < end ? now + kLookNs : end, receive, wake, spin_from);
    if (const flexloop_msgs::sensor_sample_t* s = station->samples().take()) {
      record_unanswered(*s, epoch, last_seq, r.unanswered);
      answer_sample(*station, *s, command, r, o.status);
      spin_from = s->t_ns + period_ns - spin_margin_ns;
    }
  }
  r.answered = station->answered();
  r.superseded = station->samples().superseded();
  r.resyncs = station->resyncs();
  r.resumes = station->resumes();
  r.followed = station->followed();
  r.drops = station->samples().drops();
  r.publish_failures = command.failures();
  take_report(station->report(), r);
  return r;
}

}  // namespace

ControllerLoopResult run_controller_loop(const LoopOptions& o, const artefact::LoopArtefact& loop,
                                         const std::function<void()>& ready) {
  if (o.transport == rt::TransportKind::kLcm)
    require_private_network("flexloop controller", o.link);
  return with_loop_controller(
      loop, [&](auto controller) { return run_with(std::move(controller), o, loop, ready); });
}

nlohmann::json controller_result_json(const ControllerLoopResult& r, const LoopOptions& o) {
  return {
      {"answered", r.answered},
      {"superseded", r.superseded},
      {"resyncs", r.resyncs},
      {"resumes", r.resumes},
      {"followed_held_commands", r.followed},
      {"publish_failures", r.publish_failures},
      {"controller_failure", r.controller_failure.empty() ? nlohmann::json(nullptr)
                                                          : nlohmann::json(r.controller_failure)},
      {"controller_warnings",
       {{"count", r.controller_warnings},
        {"first",
         r.first_warning.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.first_warning)}}},
      {"controller_log",
       {{"messages", r.controller_messages}, {"lost", r.controller_messages_lost}}},
      {"dropped_messages", drops_json(r.drops)},
      {"compute_ns", summary_json(*r.compute)},
      {"response_ns", summary_json(*r.response)},
      {"cpu", o.realtime.cpu},
      {"fifo", r.fifo},
      {"transport", rt::to_string(o.transport)},
      {"controller_setup", r.setup},
      {"unanswered_samples", r.unanswered.to_json()},
      {"real_time_promises", real_time_promises_json(answer_watch(r))}};
}

AnswerWatch answer_watch(const ControllerLoopResult& r) {
  return {r.allocations_counted, r.allocations, r.answers_allocating, r.answered,
          r.compute->summary(),  r.period_ns,   r.controller_failure};
}

}  // namespace flexloop::loop
