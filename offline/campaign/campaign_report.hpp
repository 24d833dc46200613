// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The report of a campaign (doc/campaign_statistics.md): summary.json (per figure the 5/50/95 %
// quantiles with their order-statistic intervals, P(unstable) with its Clopper-Pearson interval,
// their convergence over the prefixes n = 2^k of the evaluations, and for a Saltelli plan the
// Sobol indices with bootstrap intervals), report.md (the same as tables, with the pictures),
// and the PNG pictures (drawn by gnuplot, offline/report/plot.hpp).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "offline/campaign/sample_table.hpp"

namespace flexloop::campaign {

/// summary.json, report.md and the PNG pictures of a campaign into out_dir (created if missing).
/// `samples` are the shard lines (one per evaluation index), sorted by index, every index of the
/// plan present. Quantiles count the stable samples; refused and error samples are counted
/// apart, never as unstable. std::invalid_argument for samples that do not fit the plan,
/// std::runtime_error when a file cannot be written.
void write_campaign_report(const nlohmann::json& plan, const std::vector<nlohmann::json>& samples,
                           const std::string& out_dir);

/// The same from the samples' table (SampleTableBuilder: every index of the plan filled).
void write_campaign_report(const nlohmann::json& plan, const SampleTable& table,
                           const std::string& out_dir);

/// The summary alone (what summary.json holds), for callers that draw nothing.
nlohmann::json campaign_summary(const nlohmann::json& plan,
                                const std::vector<nlohmann::json>& samples);
/// The same from the table and its independent machines (machine_table(plan, table)).
nlohmann::json campaign_summary(const nlohmann::json& plan, const SampleTable& table,
                                const MachineTable& machines);

}  // namespace flexloop::campaign
