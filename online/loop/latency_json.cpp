// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/latency_json.hpp"

#include <cstdio>

namespace flexloop::loop {

nlohmann::json summary_json(const rt::LatencySummary& s) {
  return {{"min", s.min},   {"p50", s.p50}, {"p99", s.p99},
          {"p999", s.p999}, {"max", s.max}, {"count", s.count}};
}

nlohmann::json summary_json(const rt::LatencyHistogram& h) {
  return summary_json(h.summary());
}

nlohmann::json drops_json(const rt::DropCounts& drops) {
  nlohmann::json j = nlohmann::json::object();
  for (int i = 0; i < rt::kDropReasonCount; ++i) {
    const auto reason = static_cast<rt::DropReason>(i);
    j[rt::to_string(reason)] = drops[reason];
  }
  return j;
}

void print_summary(const char* what, const rt::LatencyHistogram& h) {
  const rt::LatencySummary s = h.summary();
  std::printf("%-22s min %9lld  p50 %9lld  p99 %9lld  p99.9 %9lld  max %10lld  (%lld samples)\n",
              what, static_cast<long long>(s.min), static_cast<long long>(s.p50),
              static_cast<long long>(s.p99), static_cast<long long>(s.p999),
              static_cast<long long>(s.max), static_cast<long long>(s.count));
}

nlohmann::json bins_json(const rt::LatencyHistogram& h) {
  nlohmann::json bins = nlohmann::json::array();
  for (int i = 0; i < rt::LatencyHistogram::kBins; ++i)
    if (const std::int64_t n = h.bin_count(i))
      bins.push_back({rt::LatencyHistogram::bin_lower(i), rt::LatencyHistogram::bin_upper(i), n});
  return bins;
}

}  // namespace flexloop::loop
