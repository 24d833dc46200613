// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The PNG pictures of a campaign report (gnuplot, offline/report/plot.hpp): the ECDF of each
// figure with its quantile intervals, histograms of the first natural frequencies, the
// closed-loop sigma envelope against the nominal machine, the worst figures against each
// parameter, Sobol bars with their intervals, and P(unstable) against n.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "offline/campaign/sample_table.hpp"

namespace flexloop::campaign {

struct Picture {
  std::string file;     ///< name inside out_dir
  std::string caption;  ///< one line for report.md
};

/// Draws the pictures into out_dir (which exists) from the samples' table, its independent
/// machines and their summary (campaign_summary); returns what it drew, in the order report.md
/// shows them.
std::vector<Picture> draw_campaign_pictures(const nlohmann::json& plan, const SampleTable& table,
                                            const MachineTable& machines,
                                            const nlohmann::json& summary,
                                            const std::string& out_dir);

}  // namespace flexloop::campaign
