#pragma once
// A campaign's samples (the shard lines) as columns: each evaluation's status and each figure's
// value per evaluation (NaN where the sample has none), for the report and its pictures.
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexloop::campaign {

/// "stable", "unstable", "refused: ...", anything else (error: ...).
enum class SampleStatus { kStable, kUnstable, kRefused, kError };
SampleStatus sample_status(const nlohmann::json& sample);

/// The value of a figure that a sample does not have.
inline constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

/// One figure over the evaluations, kMissing where a sample has none.
struct FigureColumn {
  std::string name;  ///< "spectral_radius", "natural_frequency_1_hz", "rms.<channel>", ...
  std::vector<double> values;
};

/// Every figure of the samples, in the summary's order: spectral_radius, natural_frequency_<r>_hz
/// (r = 1.. the most any sample has), rms.<channel>, rms_open.<channel> (channels sorted),
/// disk_margin_db, disk_margin_deg, disk_margin_all_db, disk_margin_all_deg, peak_sigma; with
/// --simulate, per channel sim.rms.<channel> and sim.rms_ratio.<channel> (sim.rms / rms), then
/// sim.saturated_share.<actuator> and sim.max_abs_command.<actuator>.
std::vector<FigureColumn> figure_columns(const std::vector<nlohmann::json>& samples);

/// The finite values of the stable samples among the first `prefix` evaluations, in order.
std::vector<double> stable_values(const FigureColumn& f, const std::vector<SampleStatus>& status,
                                  long prefix);

/// A number as JSON, null when it is not finite (JSON has no infinity).
nlohmann::json number_or_null(double v);

}  // namespace flexloop::campaign
