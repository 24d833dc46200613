// SPDX-License-Identifier: BSD-3-Clause
#include "online/hil/interleaved_baselines.hpp"

#include <algorithm>
#include <stdexcept>

#include "online/hil/baseline_json.hpp"
#include "rt/iceoryx_pingpong_baseline.hpp"
#include "rt/loop_process_setup.hpp"

namespace flexloop::hil {

std::string neighbour_port_url(const std::string& url) {
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0)
    throw std::runtime_error("LCM URL " + url + ": the baselines need a udpm:// URL");
  const std::size_t host_end = url.find_first_of(":?", scheme.size());
  if (host_end == std::string::npos || url[host_end] == '?')
    return url.substr(0, host_end) + ":7668" +
           (host_end == std::string::npos ? "" : url.substr(host_end));
  const std::size_t port_end = url.find('?', host_end);
  const std::string port = url.substr(host_end + 1, port_end - host_end - 1);
  int p = 0;
  try {
    p = std::stoi(port);
  } catch (const std::exception&) {
    throw std::runtime_error("LCM URL " + url + ": '" + port + "' is not a port");
  }
  if (p <= 0 || p >= 65535) throw std::runtime_error("LCM URL " + url + ": port out of range");
  return url.substr(0, host_end + 1) + std::to_string(p + 1) +
         (port_end == std::string::npos ? "" : url.substr(port_end));
}

rt::PingPongOptions InterleavedBaselines::pingpong_options(std::int64_t duration_ns) const {
  rt::PingPongOptions pp;
  pp.clock = settings_.clock;
  pp.receive_mode = rt::receive_mode_for(settings_.clock.wait_mode);
  pp.receive_path = settings_.receive_path;
  pp.duration_ns = duration_ns;
  pp.ping_realtime = settings_.realtime;
  pp.pong_realtime = settings_.realtime;
  pp.pong_realtime.cpu = settings_.pong_cpu;
  pp.url = settings_.url;
  return pp;
}

namespace {

void merge_pingpong(rt::PingPongResult& total, rt::PingPongResult&& segment, bool first) {
  if (first)
    total = std::move(segment);
  else
    rt::merge_into(total, segment);
}

}  // namespace

void InterleavedBaselines::measure_segment() {
  const auto duration_ns = static_cast<std::int64_t>(settings_.segment_s * 1e9);
  rt::TimerBaselineOptions timer;
  timer.clock = settings_.clock;
  timer.duration_ns = duration_ns;
  timer.realtime = settings_.realtime;
  rt::TimerBaselineResult t = rt::run_timer_baseline(timer);

  const rt::PingPongOptions pp = pingpong_options(duration_ns);
  const bool iceoryx = settings_.transport == rt::TransportKind::kIceoryx;
  if (iceoryx && settings_.roudi == nullptr)
    throw std::logic_error("an iceoryx baseline needs the run's RouDi");
  rt::PingPongResult p = iceoryx ? rt::run_iceoryx_pingpong_baseline(pp, *settings_.roudi)
                                 : rt::run_pingpong_baseline(pp);
  const bool first = segments_.empty();
  if (iceoryx) merge_pingpong(pingpong_lcm_, rt::run_pingpong_baseline(pp), first);
  if (first && settings_.floor_round_trips > 0) {
    rt::ShmPingPongOptions floor;
    floor.round_trips = settings_.floor_round_trips;
    floor.ping_realtime = pp.ping_realtime;
    floor.pong_realtime = pp.pong_realtime;
    floor_ = rt::run_shm_pingpong_baseline(floor);
  }

  segments_.push_back({.pings = p.sent,
                       .unanswered = p.unanswered,
                       .timer_cycles = t.cycles,
                       .pingpong_p99_ns = p.round_trip->percentile(0.99),
                       .timer_p99_ns = t.wakeup_lateness->percentile(0.99)});
  if (first)
    timer_ = std::move(t);
  else
    rt::merge_into(timer_, t);
  merge_pingpong(pingpong_, std::move(p), first);
}

nlohmann::json InterleavedBaselines::totals_json() const {
  if (segments_.empty()) throw std::logic_error("no baseline segment was measured");
  nlohmann::json j = {{"timer", timer_baseline_json(timer_)},
                      {"pingpong", pingpong_baseline_json(pingpong_)}};
  j["pingpong"]["transport"] = rt::to_string(settings_.transport);
  if (settings_.transport == rt::TransportKind::kIceoryx) {
    j["pingpong_lcm"] = pingpong_baseline_json(pingpong_lcm_);
    j["pingpong_lcm"]["transport"] = "lcm";
  }
  if (floor_) j["shm_floor"] = shm_pingpong_baseline_json(*floor_);
  j["segments"] = segments();
  return j;
}

namespace {

nlohmann::json spread_json(std::vector<double> v) {
  if (v.empty()) return nullptr;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return {{"median", median}, {"min", v.front()}, {"max", v.back()}};
}

}  // namespace

nlohmann::json compare_segments(const std::vector<BaselineSegment>& segments,
                                const nlohmann::json& loop_segments, const BaselineMargins& m) {
  nlohmann::json rows = nlohmann::json::array();
  std::vector<double> ratios, excess, margin_use;
  int within = 0;
  const std::size_t n = std::min(segments.size(), loop_segments.size());
  for (std::size_t k = 0; k < n; ++k) {
    const BaselineSegment& b = segments[k];
    const nlohmann::json& l = loop_segments[k];
    const auto cycles = l.value("cycles", std::int64_t{0});
    const auto misses = l.value("deadline_misses", std::int64_t{0});
    const auto rt_p99 = l.value("round_trip_p99_ns", std::int64_t{0});
    const double miss_share = cycles > 0 ? static_cast<double>(misses) / cycles : 0;
    const double unanswered_share = b.pings > 0 ? static_cast<double>(b.unanswered) / b.pings : 0;
    const double ratio = b.pingpong_p99_ns > 0 && l.value("answers", std::int64_t{0}) > 0
                             ? static_cast<double>(rt_p99) / b.pingpong_p99_ns
                             : 0;
    const double rt_allowed = m.round_trip_factor * b.pingpong_p99_ns + b.timer_p99_ns;
    const double miss_allowed = m.miss_share_factor * unanswered_share + m.miss_share_margin;
    // The larger of the two margins' uses (1 = at the margin), for the median segment.
    const double use =
        std::max(rt_allowed > 0 ? rt_p99 / rt_allowed : 0, miss_share / miss_allowed);
    const bool ok = use <= 1.0;
    within += ok ? 1 : 0;
    if (ratio > 0) ratios.push_back(ratio);
    excess.push_back(miss_share - unanswered_share);
    margin_use.push_back(use);
    rows.push_back({{"baseline",
                     {{"pings", b.pings},
                      {"unanswered", b.unanswered},
                      {"pingpong_round_trip_p99_ns", b.pingpong_p99_ns},
                      {"timer_cycles", b.timer_cycles},
                      {"timer_wakeup_lateness_p99_ns", b.timer_p99_ns}}},
                    {"loop", l},
                    {"round_trip_p99_ratio", ratio > 0 ? nlohmann::json(ratio) : nullptr},
                    {"miss_share", miss_share},
                    {"unanswered_share", unanswered_share},
                    {"margin_use", use},
                    {"within_margins", ok}});
  }
  const nlohmann::json use_spread = spread_json(margin_use);
  return {{"segments", rows},
          {"round_trip_p99_ratio", spread_json(ratios)},
          {"miss_share_minus_unanswered", spread_json(excess)},
          {"margin_use", use_spread},
          {"segments_within_margins", within},
          {"median_segment_within_margins",
           !use_spread.is_null() && use_spread["median"].get<double>() <= 1.0},
          {"margins",
           {{"miss_share_factor", m.miss_share_factor},
            {"miss_share_margin", m.miss_share_margin},
            {"round_trip_factor", m.round_trip_factor}}}};
}

}  // namespace flexloop::hil
