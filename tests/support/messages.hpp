// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Messages with their channel vectors sized (the loop's messages carry their counts), zero-filled.
#include <cstdint>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>

namespace flexloop::test {

inline flexloop_msgs::sensor_sample_t sized_sample(int sensors = 6, int performance = 6) {
  flexloop_msgs::sensor_sample_t s{};
  s.n_sensors = static_cast<std::int16_t>(sensors);
  s.n_performance = static_cast<std::int16_t>(performance);
  s.sensors.assign(static_cast<std::size_t>(sensors), 0.0);
  s.performance.assign(static_cast<std::size_t>(performance), 0.0);
  return s;
}

inline flexloop_msgs::actuator_command_t sized_command(int commands = 6) {
  flexloop_msgs::actuator_command_t c{};
  c.n_commands = static_cast<std::int16_t>(commands);
  c.commands.assign(static_cast<std::size_t>(commands), 0.0);
  return c;
}

}  // namespace flexloop::test
