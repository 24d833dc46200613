#pragma once
// TEMPORARY (campaign-core's branch): the declaration of CAMPAIGN.md, so that this branch
// compiles before campaign-stats' campaign_report.* is merged. The lead takes theirs.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexloop::campaign {

void write_campaign_report(const nlohmann::json& plan, const std::vector<nlohmann::json>& samples,
                           const std::string& out_dir);

}  // namespace flexloop::campaign
