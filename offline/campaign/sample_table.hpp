// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A campaign's samples (the shard lines) as columns: each evaluation's status and each figure's
// value per evaluation (NaN where the sample has none), for the report and its pictures. The
// columns are filled one sample at a time (SampleTableBuilder): a line is parsed, its numbers
// taken and the line dropped, so that a report holds fixed-size numbers per sample, never the
// samples (a 10^6-sample report, issue 54).
#include <cstdint>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "offline/campaign/column_spill.hpp"

namespace flexloop::campaign {

/// "stable", "unstable", "refused: ...", "marginal: ..." (judged stable, no stationary state),
/// anything else (error: ...). The counts' order: kStatusNames.
enum class SampleStatus : std::uint8_t { kStable, kUnstable, kRefused, kError, kMarginal };
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

/// The evaluations that are independent machines: every one, but of a Saltelli design
/// (plan "design" = "saltelli", d = the plan's "columns") only the A and B rows, j = 0 and 1 of
/// each block of d + 2: an A_B^i row shares d - 1 coordinates with its A row, so pooling them
/// would count one machine about d times and make every interval too narrow
/// (doc/campaign_statistics.md, "Which samples count").
std::vector<long> independent_evaluations(const nlohmann::json& plan, long total);

/// --simulate's runs over the samples: how many ran, were not run, failed; per performance
/// channel the relative standard errors (rms_standard_error / rms) of the runs that have one.
struct SimulationTally {
  long ran = 0, not_run = 0, error = 0;
  std::map<std::string, std::vector<double>> relative_standard_error;
};

/// Every evaluation as columns: what the report and its pictures are computed from.
struct SampleTable {
  std::vector<SampleStatus> status;  ///< per evaluation
  /// Every figure of the samples, per evaluation, in the summary's order: spectral_radius,
  /// natural_frequency_<r>_hz (r = 1.. the most any sample has), rms.<channel>,
  /// rms_open.<channel> (channels sorted; these three over the judged machines, the rest over
  /// the stable ones), disk_margin_db, disk_margin_deg, disk_margin_all_db,
  /// disk_margin_all_deg, peak_sigma; with --simulate, per channel sim.rms.<channel> and
  /// sim.rms_ratio.<channel> (sim.rms / rms), then sim.saturated_share.<actuator> and
  /// sim.max_abs_command.<actuator>.
  std::vector<FigureColumn> figures;
  /// Per plan column (its "columns", in order), the drawn value per evaluation (NaN: none).
  std::vector<std::vector<double>> parameters;
  /// Per frequency of the plan's sigma grid, sigma_max of the stable independent machines.
  ColumnSpill sigma;
  SimulationTally simulation;
};

/// Fills a SampleTable one sample at a time, in any order of index, each index once.
class SampleTableBuilder {
 public:
  /// For the plan's "evaluations" samples.
  explicit SampleTableBuilder(const nlohmann::json& plan);
  /// @throws std::invalid_argument for an index outside the plan.
  void add(const nlohmann::json& sample);
  SampleTable finish();

 private:
  std::vector<double>& column(std::map<std::string, std::vector<double>>& columns,
                              const std::string& name);
  void add_figures(long index, const nlohmann::json& sample);
  void add_sigma(long index, const nlohmann::json& sample);

  long evaluations_, saltelli_stride_ = 0;  // 0: every evaluation is a machine
  std::vector<std::string> parameter_paths_;
  SampleTable table_;
  // Per figure, by name: the scalar ones, the natural frequencies by rank, the channel figures
  // by field ("rms", "sim.rms", ...) then channel (sorted, as the summary lists them).
  std::map<std::string, std::vector<double>> scalars_;
  std::vector<std::vector<double>> frequencies_;
  std::map<std::string, std::map<std::string, std::vector<double>>> channels_;
};

/// The table of samples that are the plan's evaluations in index order (samples[i] of index i).
SampleTable sample_table(const nlohmann::json& plan, const std::vector<nlohmann::json>& samples);

/// The statuses and figures of the independent machines only, in evaluation order: what the
/// summary's figures and intervals and the report's pictures are computed over. When every
/// evaluation is a machine (all designs but Saltelli) the figures are the table's own, not a copy
/// (192 MB at 10^6 samples of the metrology frame): the table must outlive this.
struct MachineTable {
  std::vector<SampleStatus> status;
  /// As SampleTable::figures, restricted to those machines.
  const std::vector<FigureColumn>& figures() const { return every_one ? *every_one : picked; }

  std::vector<FigureColumn> picked;                      ///< a Saltelli design's A and B rows
  const std::vector<FigureColumn>* every_one = nullptr;  ///< else the table's figures
};
MachineTable machine_table(const nlohmann::json& plan, const SampleTable& table);

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
