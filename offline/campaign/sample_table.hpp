#pragma once
// A campaign's samples (the shard lines) as columns: each evaluation's status and each figure's
// value per evaluation (NaN where the sample has none), for the report and its pictures.
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexloop::campaign {

/// "stable", "unstable", "refused: ...", "marginal: ..." (judged stable, no stationary state),
/// anything else (error: ...). The counts' order: kStatusNames.
enum class SampleStatus { kStable, kUnstable, kRefused, kError, kMarginal };
inline constexpr const char* kStatusNames[] = {"stable", "unstable", "refused", "error",
                                               "marginal"};
/// Judged: stable, unstable or marginal (P(unstable)'s denominator).
inline bool judged(SampleStatus s) {
  return s == SampleStatus::kStable || s == SampleStatus::kUnstable || s == SampleStatus::kMarginal;
}
SampleStatus sample_status(const nlohmann::json& sample);

/// The value of a figure that a sample does not have.
inline constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

/// Which machines a figure's statistics are over (doc/campaign_statistics.md): the passive
/// machine's and the loop's poles exist for every judged machine (stable, unstable, marginal); the
/// closed loop's RMS, margins and responses are taken over the stable ones.
enum class Population { kJudged, kStable };
const char* to_string(Population p);

/// One figure over the evaluations, kMissing where a sample has none.
struct FigureColumn {
  std::string name;  ///< "spectral_radius", "natural_frequency_1_hz", "rms.<channel>", ...
  std::vector<double> values;
  Population population = Population::kStable;
};

/// Every figure of the samples, in the summary's order: spectral_radius, natural_frequency_<r>_hz
/// (r = 1.. the most any sample has), rms.<channel>, rms_open.<channel> (channels sorted; these
/// three over the judged machines, the rest over the stable ones),
/// disk_margin_db, disk_margin_deg, disk_margin_all_db, disk_margin_all_deg, peak_sigma; with
/// --simulate, per channel sim.rms.<channel> and sim.rms_ratio.<channel> (sim.rms / rms), then
/// sim.saturated_share.<actuator> and sim.max_abs_command.<actuator>.
std::vector<FigureColumn> figure_columns(const std::vector<nlohmann::json>& samples);

/// The evaluations that are independent machines: every one, but of a Saltelli design
/// (plan "design" = "saltelli", d = the plan's "columns") only the A and B rows, j = 0 and 1 of
/// each block of d + 2: an A_B^i row shares d - 1 coordinates with its A row, so pooling them
/// would count one machine about d times and make every interval too narrow
/// (doc/campaign_statistics.md, "Which samples count").
std::vector<long> independent_evaluations(const nlohmann::json& plan, long total);

/// The statuses and figures of the independent machines only, in evaluation order: what the
/// summary's figures and intervals and the report's pictures are computed over.
struct MachineTable {
  std::vector<SampleStatus> status;
  std::vector<FigureColumn> figures;  ///< as figure_columns, restricted to those machines
};
MachineTable machine_table(const nlohmann::json& plan, const std::vector<nlohmann::json>& samples);

/// The values of the figure's population among the first `prefix` evaluations, in order: every
/// number, +inf included (an unbounded disk margin is the best machine, not a missing one).
std::vector<double> population_values(const FigureColumn& f,
                                      const std::vector<SampleStatus>& status, long prefix);

/// A number as JSON, null when it is not finite (JSON has no infinity).
nlohmann::json number_or_null(double v);
/// A number as JSON; an infinity as the string "+inf" or "-inf" (an unbounded margin, the
/// order statistic of a sample that has one); null for NaN. figure_value reads it back.
nlohmann::json number_or_infinity(double v);
/// A sample's figure: the number, +-inf for "+inf" / "-inf", kMissing for anything else.
double figure_value(const nlohmann::json& j);

}  // namespace flexloop::campaign
