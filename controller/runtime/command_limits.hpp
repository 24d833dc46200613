// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Start-up: a controller's actuator limits as one value per channel, for every runtime controller
// (PI and state space alike).
#include <Eigen/Core>
#include <string>

namespace flexloop::controller::runtime {

struct CommandLimits {
  Eigen::VectorXd u_min, u_max;  ///< n values each, ±inf where unlimited
};

/// u_min, u_max as given (empty: unlimited; one value: every channel; or n values).
/// @throws std::invalid_argument "<who>: ..." for another count, NaN, or u_min > u_max.
CommandLimits command_limits(const Eigen::VectorXd& u_min, const Eigen::VectorXd& u_max,
                             Eigen::Index n, const std::string& who);

}  // namespace flexloop::controller::runtime
