// SPDX-License-Identifier: BSD-3-Clause
#include "offline/report/run_log.hpp"

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "common/input_error.hpp"
#include "offline/report/table_file.hpp"

namespace flexloop::report {

namespace {

constexpr const char* kChannelMap = "FLEXLOOP_CHANNEL_MAP";  // online/loop/channel_map.hpp

struct Channels {
  std::vector<std::string> sensors, performance, actuators;  // "name [unit]"
};

Channels channel_map(const std::string& text, const std::string& path) {
  Channels c;
  try {
    const auto j = nlohmann::json::parse(text);
    const auto list = [&](const char* kind) {
      std::vector<std::string> out;
      for (const auto& e : j.at("channels").at(kind))
        out.push_back(e.at("name").get<std::string>() + " [" + e.at("unit").get<std::string>() +
                      "]");
      return out;
    };
    c.sensors = list("sensors");
    c.performance = list("performance");
    c.actuators = list("actuators");
  } catch (const nlohmann::json::exception& e) {
    throw common::InputError(
        path, std::string("channel ") + kChannelMap + ": not a channel map: " + e.what());
  }
  return c;
}

struct Sample {
  std::int64_t t_ns = 0;
  std::vector<double> sensors, performance, commands;
};

// The event's message of type Message (named `type` in the error).
template <class Message>
Message decoded(const lcm::LogEvent& e, const std::string& path, const char* type) {
  Message m;
  if (m.decode(e.data, 0, static_cast<int>(e.datalen)) != static_cast<int>(e.datalen))
    throw common::InputError(path, "event " + std::to_string(e.eventnum) + ": " + e.channel +
                                       " does not decode as this flexloop's " + type +
                                       " (a log of another version of msgs/?)");
  return m;
}

}  // namespace

RunTable read_run_log(const std::string& path) {
  if (!std::filesystem::exists(path)) throw common::InputError(path, "cannot open the log file");
  lcm::LogFile log(path, "r");
  if (!log.good()) throw common::InputError(path, "cannot be read as an LCM log");
  std::string map_text;
  std::map<std::int64_t, Sample> samples;                                        // by seq
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<double>> answers;  // (epoch, seq)
  std::int64_t epoch = 0;
  bool have_epoch = false;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const std::string channel = e->channel;
    if (channel == kChannelMap) {
      map_text.assign(static_cast<const char*>(e->data), static_cast<std::size_t>(e->datalen));
    } else if (channel == "FLEXLOOP_SENSOR") {
      const auto s = decoded<flexloop_msgs::sensor_sample_t>(*e, path, "sensor_sample_t");
      // One plant run per table: the first epoch in the log.
      if (!have_epoch) epoch = s.plant_epoch, have_epoch = true;
      if (s.plant_epoch != epoch) continue;
      samples[s.seq] = {s.t_ns, s.sensors, s.performance, {}};
    } else if (channel == "FLEXLOOP_COMMAND") {
      const auto c = decoded<flexloop_msgs::actuator_command_t>(*e, path, "actuator_command_t");
      answers.emplace(std::pair{c.plant_epoch, c.answers_seq}, c.commands);
    }
  }
  if (map_text.empty())
    throw common::InputError(path, std::string("no channel map (channel ") + kChannelMap +
                                       "): record the run with `flexloop hil --lcm-log FILE`");
  const Channels ch = channel_map(map_text, path);
  RunTable t;
  t.loop = nlohmann::json::parse(map_text).value("loop", "");
  t.names = {"t_s", "seq"};
  for (const auto& n : ch.sensors) t.names.push_back("sensor " + n);
  for (const auto& n : ch.performance) t.names.push_back("performance " + n);
  for (const auto& n : ch.actuators) t.names.push_back("command " + n);
  t.columns.assign(t.names.size(), {});
  const std::int64_t t0 = samples.empty() ? 0 : samples.begin()->second.t_ns;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [seq, s] : samples) {
    if (s.sensors.size() != ch.sensors.size() || s.performance.size() != ch.performance.size())
      throw common::InputError(path, "sample " + std::to_string(seq) + ": " +
                                         std::to_string(s.sensors.size()) + " sensors and " +
                                         std::to_string(s.performance.size()) +
                                         " performance channels; the channel map has " +
                                         std::to_string(ch.sensors.size()) + " and " +
                                         std::to_string(ch.performance.size()));
    std::size_t k = 0;
    t.columns[k++].push_back(static_cast<double>(s.t_ns - t0) * 1e-9);
    t.columns[k++].push_back(static_cast<double>(seq));
    for (const double v : s.sensors) t.columns[k++].push_back(v);
    for (const double v : s.performance) t.columns[k++].push_back(v);
    const auto a = answers.find({epoch, seq});
    const bool answered = a != answers.end() && a->second.size() == ch.actuators.size();
    t.answered += answered ? 1 : 0;
    for (std::size_t i = 0; i < ch.actuators.size(); ++i)
      t.columns[k++].push_back(answered ? a->second[i] : nan);
  }
  return t;
}

void write_run_table(const RunTable& t, const std::string& path) {
  const Eigen::Index rows = t.columns.empty() ? 0 : static_cast<Eigen::Index>(t.columns[0].size());
  Eigen::MatrixXd data(rows, static_cast<Eigen::Index>(t.columns.size()));
  for (std::size_t j = 0; j < t.columns.size(); ++j)
    data.col(static_cast<Eigen::Index>(j)) =
        Eigen::Map<const Eigen::VectorXd>(t.columns[j].data(), rows);
  write_table(path, t.names, data);
}

}  // namespace flexloop::report
