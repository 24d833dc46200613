// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The uncertain parameters file (U.toml, doc/campaign.md): which numbers of a machine's model
// and scene vary from unit to unit, how (a distribution), and whether one draw is shared by all
// the numbers a glob matches; and [campaign] controller = "frozen" | "redesigned". Read as
// strictly as a scene: bad input throws flexloop::InputError "file:line: what is wrong".
// What a path names (and the nominal values) is known only with the machine: the planning step
// (offline/campaign/planned_parameters.hpp) matches the paths and judges the draws.
#include <optional>
#include <string>
#include <vector>

#include "offline/campaign/distributions.hpp"

namespace flexloop::campaign {

enum class DrawMode { kEach, kShared };

/// One [[parameter]] entry as written (a number not written is nullopt).
struct UncertainParameter {
  std::string path;   ///< "element.<id>.<key>", "node.<id>.mass", "effects.actuator.gain", globs
  std::string place;  ///< "file:line" of the entry
  DistributionKind kind = DistributionKind::kUniform;
  std::optional<double> low, high, mean, sd, relative_sd, median;
  DrawMode draw = DrawMode::kEach;
};

struct UncertainParameters {
  std::string file;
  std::vector<UncertainParameter> parameters;
  std::string controller = "frozen";  ///< "frozen" | "redesigned"
};

UncertainParameters parse_uncertain_parameters(const std::string& toml_text,
                                               const std::string& file);
UncertainParameters load_uncertain_parameters(const std::string& path);

/// The distribution of one concrete number whose nominal value is `nominal` (the default mean
/// or median; relative_sd is relative to the mean or median).
/// @throws flexloop::InputError at the entry when it gives a zero spread (relative_sd of a
///         nominal zero) or a lognormal of a non-positive median.
Distribution distribution_at(const UncertainParameter& p, double nominal);

std::string draw_name(DrawMode mode);

}  // namespace flexloop::campaign
