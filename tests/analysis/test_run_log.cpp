// SPDX-License-Identifier: BSD-3-Clause
// `flexloop log`: a recorded run (an LCM log with the channel map, sensor samples and commands)
// round-trips into CSV and .mat tables with named columns; the answer of each sample sits on its
// row (NaN where none came); another plant run in the same log is left out; a log without a
// channel map and an unknown output format are refused naming the file.
#include <matio.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>

#include "offline/report/run_log.hpp"

using namespace flexloop;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("flexloop_run_log_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

template <class Message>
void write(lcm::LogFile& log, const std::string& channel, const Message& m) {
  std::vector<char> buffer(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
  lcm::LogEvent e{};
  e.timestamp = 0;
  e.channel = channel;
  e.datalen = static_cast<int32_t>(buffer.size());
  e.data = buffer.data();
  REQUIRE(log.writeEvent(&e) == 0);
}

void write_text(lcm::LogFile& log, const std::string& channel, std::string text) {
  lcm::LogEvent e{};
  e.channel = channel;
  e.datalen = static_cast<int32_t>(text.size());
  e.data = text.data();
  REQUIRE(log.writeEvent(&e) == 0);
}

flexloop_msgs::sensor_sample_t sample(std::int64_t seq, std::int64_t epoch) {
  flexloop_msgs::sensor_sample_t s{};
  s.t_ns = 1'000'000'000 + seq * 100'000;  // 10 kHz
  s.seq = seq;
  s.plant_epoch = epoch;
  s.n_sensors = 2;
  s.n_performance = 1;
  s.sensors = {0.5 * static_cast<double>(seq), -1.0 * static_cast<double>(seq)};
  s.performance = {1e-3 * static_cast<double>(seq)};
  return s;
}

flexloop_msgs::actuator_command_t answer(std::int64_t seq, std::int64_t epoch) {
  flexloop_msgs::actuator_command_t c{};
  c.seq = seq;
  c.answers_seq = seq;
  c.plant_epoch = epoch;
  c.n_commands = 3;
  c.commands = {10.0 * static_cast<double>(seq), 0.25, -2.0};
  return c;
}

// A run of samples 1..4 (epoch 7) whose sample 3 is not answered, an answer and a sample of other
// runs.
fs::path recorded_run(const fs::path& dir, bool with_map = true) {
  const fs::path file = dir / (with_map ? "run.lcmlog" : "no_map.lcmlog");
  lcm::LogFile log(file.string(), "w");
  REQUIRE(log.good());
  if (with_map)
    write_text(log, "FLEXLOOP_CHANNEL_MAP",
               R"({"format": "flexloop channel map", "loop": "two_by_three", "rate_hz": 10000,
                  "channels": {"sensors": [{"name": "f1", "unit": "N"}, {"name": "f2", "unit": "N"}],
                               "performance": [{"name": "a1", "unit": "m/s^2"}],
                               "disturbances": [{"name": "w1", "unit": "m/s^2"}],
                               "actuators": [{"name": "u1", "unit": "N"}, {"name": "u2", "unit": "N"},
                                             {"name": "u3", "unit": "N"}]}})");
  // A straggler of the previous plant run (epoch 6), logged before this run's first sample.
  auto straggler = answer(2, 6);
  straggler.commands = {999.0, 999.0, 999.0};
  write(log, "FLEXLOOP_COMMAND", straggler);
  for (std::int64_t k = 1; k <= 4; ++k) {
    write(log, "FLEXLOOP_SENSOR", sample(k, 7));
    if (k != 3) write(log, "FLEXLOOP_COMMAND", answer(k, 7));
  }
  write(log, "FLEXLOOP_SENSOR", sample(1, 8));  // the plant restarted: another run
  return file;
}

}  // namespace

TEST_CASE("run log: a recorded run exports to CSV and .mat with named columns", "[report][log]") {
  TempDir dir;
  const auto t = report::read_run_log(recorded_run(dir.path).string());
  CHECK(t.loop == "two_by_three");
  const std::vector<std::string> names{"t_s",
                                       "seq",
                                       "sensor f1 [N]",
                                       "sensor f2 [N]",
                                       "performance a1 [m/s^2]",
                                       "command u1 [N]",
                                       "command u2 [N]",
                                       "command u3 [N]"};
  REQUIRE(t.names == names);
  REQUIRE(t.columns[0].size() == 4);  // the other run's sample is not in the table
  CHECK(t.answered == 3);
  CHECK(t.columns[0][3] == Approx(3e-4).epsilon(1e-12));
  CHECK(t.columns[1][2] == 3);
  CHECK(t.columns[3][1] == -2.0);
  CHECK(t.columns[4][3] == 4e-3);
  CHECK(t.columns[5][1] == 20.0);      // this run's answer, not the other run's straggler
  CHECK(std::isnan(t.columns[5][2]));  // sample 3 has no answer

  SECTION("CSV") {
    const fs::path csv = dir.path / "run.csv";
    report::write_run_table(t, csv.string());
    std::ifstream in(csv);
    std::string header, row;
    std::getline(in, header);
    CHECK_THAT(header, Contains("sensor f1 [N]") && Contains("command u3 [N]"));
    // Every row reads back to the table's numbers exactly ("nan" for the missing answer).
    for (std::size_t r = 0; r < 4; ++r) {
      REQUIRE(std::getline(in, row));
      std::stringstream fields(row);
      std::string field;
      for (std::size_t j = 0; j < names.size(); ++j) {
        REQUIRE(std::getline(fields, field, ','));
        const double v = std::stod(field);
        CAPTURE(r, j, field);
        if (std::isnan(t.columns[j][r]))
          CHECK(std::isnan(v));
        else
          CHECK(v == t.columns[j][r]);
      }
    }
  }
  SECTION(".mat") {
    const fs::path mat_file = dir.path / "run.mat";
    report::write_run_table(t, mat_file.string());
    mat_t* mat = Mat_Open(mat_file.string().c_str(), MAT_ACC_RDONLY);
    REQUIRE(mat != nullptr);
    matvar_t* data = Mat_VarRead(mat, "data");
    REQUIRE(data != nullptr);
    REQUIRE(data->rank == 2);
    CHECK(data->dims[0] == 4);
    CHECK(data->dims[1] == 8);
    const auto* v = static_cast<const double*>(data->data);
    CHECK(v[5 * 4 + 1] == 20.0);  // column-major: command u1 of sample 2
    CHECK(v[3 * 4 + 1] == -2.0);
    matvar_t* columns = Mat_VarRead(mat, "columns");
    REQUIRE(columns != nullptr);
    matvar_t* name = Mat_VarGetCell(columns, 4);
    REQUIRE(name != nullptr);
    CHECK(std::string(static_cast<const char*>(name->data), name->dims[1]) ==
          "performance a1 [m/s^2]");
    Mat_VarFree(columns);
    Mat_VarFree(data);
    Mat_Close(mat);
  }
}

TEST_CASE("run log: bad input is refused naming the file", "[report][log]") {
  TempDir dir;
  const fs::path no_map = recorded_run(dir.path, false);
  CHECK_THROWS_WITH(report::read_run_log(no_map.string()),
                    Contains(no_map.string()) && Contains("no channel map"));
  const auto t = report::read_run_log(recorded_run(dir.path).string());
  CHECK_THROWS_WITH(report::write_run_table(t, (dir.path / "run.xlsx").string()),
                    Contains("run.xlsx") && Contains(".csv or .mat"));
  CHECK_FALSE(fs::exists(dir.path / "run.xlsx"));
  CHECK_THROWS_WITH(report::read_run_log((dir.path / "missing.lcmlog").string()),
                    Contains("missing.lcmlog"));
}
