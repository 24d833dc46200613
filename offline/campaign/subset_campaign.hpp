// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// P(unstable) of a fleet by subset simulation (`flexloop campaign SCENE -u U.toml -n N --method
// subset`, issue 54 item 3.2; doc/campaign.md "Rare failures"): the plan's uncertain parameters
// as a point z of the standard normal space, u_i = Phi(z_i) each column's unit coordinate and its
// inverse CDF the value (as a design's point becomes a machine), the machine judged by the
// SampleEvaluator, and its failure margin g the limit state of offline/campaign/
// subset_simulation.hpp. Failure is g >= 0:
//   unstable              spectral_radius - 1, at least 0 (a loop unstable only continuous
//                         counts, with 0)
//   refused, error        +inf: a machine not judged counts as failing, the most (it must not
//                         vanish); the estimate is then P(unstable, refused or failed)
//   stable, marginal      margin "radius": largest_inner_radius - 1 (the poles inside the unit
//                         circle; the integrator's on it left out); margin "disk":
//                         -disk_margin_db (-inf for an unbounded disk; 0- when not computed);
//                         both below 0 (0- at worst).
// The evaluations run one after the other in this process (the evaluator is not shown to be
// thread-safe); each is appended to samples.jsonl as it is computed.
#include <cstdint>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "offline/campaign/subset_simulation.hpp"

namespace flexloop::campaign {

enum class FailureMargin { kRadius, kDisk };
/// "radius" | "disk"; flexloop::InputError naming --margin otherwise.
FailureMargin failure_margin_from_name(const std::string& name);
std::string failure_margin_name(FailureMargin margin);

/// g of one sample line (the JSONL object of plan_samples.hpp), as above.
double failure_margin(const nlohmann::json& sample, FailureMargin margin);

struct SubsetCampaignOptions {
  SubsetSettings settings;  ///< per_level = -n, seed = the plan's
  FailureMargin margin = FailureMargin::kRadius;
  std::string samples_path;  ///< every evaluated machine's line, in evaluation order
  SubsetLevelDone level_done;
};

struct SubsetCampaign {
  SubsetResult result;
  nlohmann::json counts;  ///< {stable, unstable, marginal, refused, error, total} of evaluations
};

/// Runs subset simulation over the plan's machines. @throws flexloop::InputError for a plan of
/// a simulated campaign (--simulate) or settings subset_simulation refuses.
SubsetCampaign run_subset_campaign(const nlohmann::json& plan, const SubsetCampaignOptions& o);

/// summary.json of a subset campaign: the inputs (scene, model, uncertain file with their
/// hashes, controller, columns, seed), `p_unstable` {estimate, cov, lo, hi, confidence,
/// interval, evaluations, method: "subset", reached_failure}, `levels` and `counts`.
nlohmann::json subset_summary(const nlohmann::json& plan, const SubsetCampaignOptions& o,
                              const SubsetCampaign& c);
/// report.md's text for that summary.
std::string subset_report_markdown(const nlohmann::json& summary);

}  // namespace flexloop::campaign
