// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: what the loop does with received LCM datagrams (rt/message_inbox.hpp: fingerprint,
// channel counts read before the decode, the generated decode, finite values, the order gate).
// The input is a sequence of datagrams, each [type (1 byte), length (2 bytes LE), bytes]; the
// type byte's low two bits pick the message type, the next bit whether the inbox expects the
// loop's counts (3 and 2) or takes any. Whatever arrives, an accepted message carries counts in
// 1..64 (or the expected ones) and finite numbers only; a violation traps. Crashes and sanitizer
// reports are findings (tools/fuzz; the corpus replays in every test run).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "rt/message_inbox.hpp"

namespace {

using namespace flexloop;

template <class Msg>
bool counts_ok(const Msg& m, rt::ChannelCounts expected);

template <>
bool counts_ok(const flexloop_msgs::sensor_sample_t& m, rt::ChannelCounts e) {
  const auto ok = [](int n, int want) {
    return want > 0 ? n == want : n >= 1 && n <= flexloop::numeric::kMaxChannels;
  };
  return ok(m.n_sensors, e.first) && ok(m.n_performance, e.second) &&
         static_cast<int>(m.sensors.size()) == m.n_sensors &&
         static_cast<int>(m.performance.size()) == m.n_performance;
}

template <>
bool counts_ok(const flexloop_msgs::actuator_command_t& m, rt::ChannelCounts e) {
  const bool n_ok = e.first > 0
                        ? m.n_commands == e.first
                        : m.n_commands >= 1 && m.n_commands <= flexloop::numeric::kMaxChannels;
  return n_ok && static_cast<int>(m.commands.size()) == m.n_commands;
}

template <>
bool counts_ok(const flexloop_msgs::loop_stats_t&, rt::ChannelCounts) {
  return true;
}

template <class Msg>
void offer(rt::MessageInbox<Msg>& inbox, rt::ChannelCounts expected, const std::uint8_t* data,
           int size, std::int64_t now_ns) {
  if (!inbox.offer(data, size, now_ns).has_value()) {
    const Msg* m = inbox.take();
    if (m == nullptr || !counts_ok(*m, expected) || !rt::all_finite(*m)) __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const rt::ChannelCounts loop_counts{3, 2}, any{};
  rt::MessageInbox<flexloop_msgs::sensor_sample_t> samples_fixed(rt::OrderGate{}, loop_counts),
      samples_any;
  rt::MessageInbox<flexloop_msgs::actuator_command_t> commands_fixed(rt::OrderGate{}, {2, 0}),
      commands_any;
  rt::MessageInbox<flexloop_msgs::loop_stats_t> stats;
  std::int64_t now_ns = 1'000'000;
  std::size_t at = 0;
  while (at + 3 <= size) {
    const std::uint8_t type = data[at];
    const std::size_t length = data[at + 1] | (static_cast<std::size_t>(data[at + 2]) << 8);
    at += 3;
    const std::size_t n = length < size - at ? length : size - at;
    const std::uint8_t* bytes = data + at;
    const int len = static_cast<int>(n);
    at += n;
    now_ns += 100'000;
    const bool fixed = (type & 4) != 0;
    switch (type & 3) {
      case 0:
        offer(fixed ? samples_fixed : samples_any, fixed ? loop_counts : any, bytes, len, now_ns);
        break;
      case 1:
        offer(fixed ? commands_fixed : commands_any, fixed ? rt::ChannelCounts{2, 0} : any, bytes,
              len, now_ns);
        break;
      default:
        offer(stats, any, bytes, len, now_ns);
        break;
    }
  }
  return 0;
}
