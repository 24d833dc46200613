#include "offline/report/run_log.hpp"

#include <fcntl.h>
#include <matio.h>
#include <unistd.h>

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
#include "offline/report/csv_writer.hpp"

namespace flexloop::report {

namespace {

constexpr const char* kChannelMap = "FLEXLOOP_CHANNEL_MAP";  // online/hil/lcm_logger.hpp

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
    throw InputError(path,
                     std::string("channel ") + kChannelMap + ": not a channel map: " + e.what());
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
    throw InputError(path, "event " + std::to_string(e.eventnum) + ": " + e.channel +
                               " does not decode as this flexloop's " + type +
                               " (a log of another version of msgs/?)");
  return m;
}

}  // namespace

RunTable read_run_log(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "cannot open the log file");
  lcm::LogFile log(path, "r");
  if (!log.good()) throw InputError(path, "cannot be read as an LCM log");
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
    throw InputError(path, std::string("no channel map (channel ") + kChannelMap +
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
      throw InputError(path, "sample " + std::to_string(seq) + ": " +
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

namespace {

void write_mat(const RunTable& t, const std::string& path) {
  const std::size_t rows = t.columns.empty() ? 0 : t.columns[0].size(), cols = t.columns.size();
  std::vector<double> data(rows * cols);  // column-major, as MATLAB stores it
  for (std::size_t j = 0; j < cols; ++j)
    for (std::size_t i = 0; i < rows; ++i) data[j * rows + i] = t.columns[j][i];
  const std::string tmp = path + ".tmp";
  mat_t* mat = Mat_CreateVer(tmp.c_str(), nullptr, MAT_FT_MAT5);
  if (!mat) throw std::runtime_error(path + ": cannot be written");
  std::size_t dims[2] = {rows, cols};
  matvar_t* d = Mat_VarCreate("data", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data.data(), 0);
  std::size_t cell_dims[2] = {1, cols};
  matvar_t* names = Mat_VarCreate("columns", MAT_C_CELL, MAT_T_CELL, 2, cell_dims, nullptr, 0);
  bool ok = d && names;
  for (std::size_t j = 0; ok && j < cols; ++j) {
    std::size_t char_dims[2] = {1, t.names[j].size()};
    matvar_t* s = Mat_VarCreate(nullptr, MAT_C_CHAR, MAT_T_UTF8, 2, char_dims,
                                const_cast<char*>(t.names[j].data()), MAT_F_DONT_COPY_DATA);
    ok = s != nullptr;
    if (ok) Mat_VarSetCell(names, static_cast<int>(j), s);
  }
  ok = ok && Mat_VarWrite(mat, d, MAT_COMPRESSION_NONE) == 0 &&
       Mat_VarWrite(mat, names, MAT_COMPRESSION_NONE) == 0;
  if (d) Mat_VarFree(d);
  if (names) Mat_VarFree(names);
  ok = Mat_Close(mat) == 0 && ok;
  // On disk before it replaces the target (as common/atomic_file.hpp does for every other file).
  if (ok) {
    const int fd = ::open(tmp.c_str(), O_RDONLY);
    ok = fd >= 0 && ::fsync(fd) == 0;
    if (fd >= 0) ::close(fd);
  }
  if (!ok) {
    std::filesystem::remove(tmp);
    throw std::runtime_error(path + ": cannot be written");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace

void write_run_table(const RunTable& t, const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".csv")
    write_csv_columns(path, t.names, t.columns);
  else if (ext == ".mat")
    write_mat(t, path);
  else
    throw InputError(path, "the output is .csv or .mat (got '" + ext + "')");
}

}  // namespace flexloop::report
