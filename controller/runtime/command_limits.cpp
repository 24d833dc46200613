// SPDX-License-Identifier: BSD-3-Clause
#include "controller/runtime/command_limits.hpp"

#include <limits>
#include <stdexcept>

namespace flexloop::controller::runtime {

namespace {

Eigen::VectorXd per_channel(const Eigen::VectorXd& v, Eigen::Index n, double none,
                            const std::string& who, const char* name) {
  if (v.size() == 0) return Eigen::VectorXd::Constant(n, none);
  if (v.size() == 1) return Eigen::VectorXd::Constant(n, v(0));
  if (v.size() != n)
    throw std::invalid_argument(who + ": " + name + " has " + std::to_string(v.size()) +
                                " values, expected 1 or " + std::to_string(n));
  return v;
}

}  // namespace

CommandLimits command_limits(const Eigen::VectorXd& u_min, const Eigen::VectorXd& u_max,
                             Eigen::Index n, const std::string& who) {
  const double inf = std::numeric_limits<double>::infinity();
  CommandLimits l{per_channel(u_min, n, -inf, who, "u_min"),
                  per_channel(u_max, n, inf, who, "u_max")};
  if (l.u_min.hasNaN() || l.u_max.hasNaN() || (l.u_min.array() > l.u_max.array()).any())
    throw std::invalid_argument(who + ": u_min must be <= u_max in every channel");
  return l;
}

}  // namespace flexloop::controller::runtime
