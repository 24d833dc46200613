// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The figures of a latency histogram and of dropped-message counts as JSON and as one printed
// line, shared by `flexloop baseline`, the plant and controller processes and the hil report, so
// that every report names its figures alike: {min, p50, p99, p999, max, count} in ns, and
// {decode_failure, non_finite, stale, duplicate, out_of_order}. Reporting only (allocates).
#include <nlohmann/json.hpp>

#include "rt/latency_histogram.hpp"
#include "rt/message_validation.hpp"

namespace flexloop::loop {

nlohmann::json summary_json(const rt::LatencySummary& s);
nlohmann::json summary_json(const rt::LatencyHistogram& h);
/// {"<reason>": count, ...} over every DropReason.
nlohmann::json drops_json(const rt::DropCounts& drops);
/// "what   min ...  p50 ...  p99 ...  p99.9 ...  max ...  (n samples)" on stdout.
void print_summary(const char* what, const rt::LatencyHistogram& h);
/// The non-empty bins as [[lower_ns, upper_ns, count], ...], for drawing the histogram later.
nlohmann::json bins_json(const rt::LatencyHistogram& h);

}  // namespace flexloop::loop
