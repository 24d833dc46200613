// SPDX-License-Identifier: BSD-3-Clause
// Report writers: CSV round trip (read back with std::ifstream, compared exactly), atomic write,
// and one PNG per plot kind (file exists and starts with the PNG signature), errors when gnuplot
// is missing or fails. Set FLEXLOOP_KEEP_TEST_OUTPUT=1 to keep the pictures for inspection.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "offline/report/csv_writer.hpp"
#include "offline/report/plot.hpp"
#include "plant/lti/frequency_response.hpp"

namespace fs = std::filesystem;
namespace report = flexloop::report;
namespace lti = flexloop::plant::lti;

namespace {
// A directory per test case, removed afterwards unless FLEXLOOP_KEEP_TEST_OUTPUT is set (then
// the pictures of all sections stay side by side).
struct ScratchDir {
  fs::path path;
  explicit ScratchDir(const std::string& name)
      : path(fs::temp_directory_path() / ("flexloop-test-analysis-" + std::to_string(::getpid())) /
             name) {
    fs::create_directories(path);
  }
  ~ScratchDir() {
    if (!std::getenv("FLEXLOOP_KEEP_TEST_OUTPUT")) fs::remove_all(path.parent_path());
  }
  std::string operator/(const std::string& file) const { return (path / file).string(); }
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path))
      names.push_back(e.path().filename().string());
    return names;
  }
};

bool is_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char sig[8] = {};
  in.read(reinterpret_cast<char*>(sig), 8);
  const unsigned char expected[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return in.gcount() == 8 && std::equal(sig, sig + 8, expected) && fs::file_size(path) > 1000;
}

// Two lightly damped modes, two inputs, two outputs: open loop, and the same with 150 x the damping
// standing in for a closed loop.
lti::StateSpace two_mode_system(double damping) {
  const double m1 = 1.0, m2 = 0.5, k1 = 4.0e3, k2 = 2.0e4;
  Eigen::MatrixXd M(2, 2), K(2, 2), Dm(2, 2);
  M << m1, 0, 0, m2;
  K << k1 + k2, -k2, -k2, k2;
  Dm = damping * K;
  const Eigen::MatrixXd Mi = M.inverse();
  lti::StateSpace s;
  s.A = Eigen::MatrixXd::Zero(4, 4);
  s.A.topRightCorner(2, 2).setIdentity();
  s.A.bottomLeftCorner(2, 2) = -Mi * K;
  s.A.bottomRightCorner(2, 2) = -Mi * Dm;
  s.B = Eigen::MatrixXd::Zero(4, 2);
  s.B.bottomRows(2) = Mi;
  s.C = Eigen::MatrixXd::Zero(2, 4);
  s.C.leftCols(2).setIdentity();
  s.D = Eigen::MatrixXd::Zero(2, 2);
  s.states = {"x1", "x2", "v1", "v2"};
  s.inputs = {"f1", "f2"};
  s.outputs = {"x1", "x2"};
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ',')) out.push_back(field);
  return out;
}
}  // namespace

TEST_CASE("CSV: numbers round trip exactly through a file", "[report][csv]") {
  ScratchDir dir("csv");
  Eigen::MatrixXd data(4, 3);
  data << 1.0 / 3.0, -2.5e17, 6.02214076e23,  //
      1e-300, 0.0, -0.1,                      //
      M_PI, std::nextafter(1.0, 2.0), -7.0,   //
      123456789.0, 5e-324, 1.7976931348623157e308;
  const std::string path = dir / "table.csv";
  report::write_csv(path, {"f [Hz]", "gain, dB", "phase \"deg\""}, data);

  std::ifstream in(path);
  REQUIRE(in);
  std::string line;
  REQUIRE(std::getline(in, line));
  CHECK(line == "f [Hz],\"gain, dB\",\"phase \"\"deg\"\"\"");
  Eigen::Index row = 0;
  while (std::getline(in, line)) {
    const auto fields = split(line);
    REQUIRE(fields.size() == 3);
    REQUIRE(row < data.rows());
    for (Eigen::Index j = 0; j < 3; ++j) {
      std::istringstream is(fields[static_cast<std::size_t>(j)]);
      double v = 0.0;
      is >> v;
      INFO("row " << row << " col " << j << " text " << fields[static_cast<std::size_t>(j)]);
      CHECK(v == data(row, j));  // bit-exact: shortest round-trip formatting
    }
    ++row;
  }
  CHECK(row == data.rows());
  CHECK(dir.files() == std::vector<std::string>{"table.csv"});  // no temporary left over
}

TEST_CASE("CSV: a log longer than the writer's block round-trips every value exactly",
          "[report][csv]") {
  // 40 000 rows x 31 columns (a sim log's width) is ~25 MB of text, several of the writer's
  // blocks; read as RunLog holds it: a column-major view with an outer stride beyond its rows.
  ScratchDir dir("csv_long");
  constexpr Eigen::Index rows = 40000, cols = 31, stride = rows + 7;
  std::vector<double> memory(static_cast<std::size_t>(stride * cols));
  std::uint64_t bits = 0x9E3779B97F4A7C15ull;  // every bit pattern of a double is fair game
  for (double& v : memory) {
    bits ^= bits << 13, bits ^= bits >> 7, bits ^= bits << 17;  // xorshift64
    std::memcpy(&v, &bits, sizeof v);
  }
  const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> data(
      memory.data(), rows, cols, Eigen::OuterStride<>(stride));
  std::vector<std::string> names;
  for (Eigen::Index j = 0; j < cols; ++j) names.push_back("c" + std::to_string(j));
  const std::string path = dir / "log.csv";
  report::write_csv(path, names, data);

  std::ifstream in(path);
  std::stringstream all;
  all << in.rdbuf();
  const std::string text = all.str();
  const char* p = text.c_str() + text.find('\n') + 1;
  Eigen::Index mismatches = 0, nans = 0;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) {
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      REQUIRE(end != p);
      REQUIRE(*end == (j + 1 < cols ? ',' : '\n'));
      p = end + 1;
      if (std::isnan(data(i, j))) {
        nans += 1;
        mismatches += std::isnan(v) ? 0 : 1;
      } else {
        mismatches += v == data(i, j) ? 0 : 1;  // bit-exact (the sign of zero aside)
      }
    }
  CHECK(mismatches == 0);
  CHECK(nans > 0);    // the NaN patterns were written and read back as nan
  CHECK(*p == '\0');  // nothing after the last row
  CHECK(dir.files() == std::vector<std::string>{"log.csv"});
}

TEST_CASE("CSV: columns form, overwrite, size and path errors", "[report][csv]") {
  ScratchDir dir("csv2");
  const std::string path = dir / "cols.csv";
  report::write_csv(path, {"a"}, Eigen::MatrixXd::Constant(2, 1, 9.0));
  report::write_csv_columns(path, {"t [s]", "y [m]"}, {{0.0, 0.5, 1.0}, {1.0, -2.0, 0.25}});
  std::ifstream in(path);
  std::stringstream all;
  all << in.rdbuf();
  CHECK(all.str() == "t [s],y [m]\n0,1\n0.5,-2\n1,0.25\n");
  CHECK_THROWS_AS(report::write_csv_columns(path, {"a", "b"}, {{1.0}, {1.0, 2.0}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(report::write_csv(path, {"a"}, Eigen::MatrixXd::Zero(1, 2)),
                  std::invalid_argument);
  CHECK_THROWS_WITH(
      report::write_csv(dir / "no/such/dir/x.csv", {"a"}, Eigen::MatrixXd::Zero(1, 1)),
      Catch::Contains("no/such/dir/x.csv"));
  CHECK(report::format_number(std::nan("")) == "nan");
  CHECK(report::format_number(-HUGE_VAL) == "-inf");
}

TEST_CASE("plots: one PNG per kind", "[report][plot]") {
  ScratchDir dir("plots");
  const auto f = lti::log_frequency_grid_hz(0.01, 1000.0, 400);
  const auto open = lti::frequency_response(two_mode_system(2e-5), f);
  const auto closed = lti::frequency_response(two_mode_system(3e-3), f);

  SECTION("Bode") {
    const std::string png = dir / "bode.png";
    report::plot_bode({"two-mode plant, x1/f1 and x2/f1", "", "|G| [dB re 1 m/N]"},
                      {{"x1/f1 open loop", f, report::channel(open, 0, 0), ""},
                       {"x2/f1 open loop", f, report::channel(open, 1, 0), ""},
                       {"x1/f1 damped", f, report::channel(closed, 0, 0), "lines lw 2 dt 2"}},
                      png);
    CHECK(is_png(png));
    CHECK_THROWS_AS(report::channel(open, 2, 0), std::invalid_argument);
  }
  SECTION("singular values, open solid and closed dashed") {
    const std::string png = dir / "sigma.png";
    report::plot_singular_values(
        {"singular values, force to displacement", "frequency [Hz]", "sigma(G) [dB re 1 m/N]"},
        {{"open loop", f, lti::singular_values(open), ""},
         {"closed loop", f, lti::singular_values(closed), ""}},
        png);
    CHECK(is_png(png));
  }
  SECTION("xy lines (time series)") {
    std::vector<double> t, y1, y2;
    for (int i = 0; i <= 500; ++i) {
      t.push_back(i * 1e-3);
      y1.push_back(std::exp(-3.0 * t.back()) * std::sin(2 * M_PI * 12 * t.back()));
      y2.push_back(0.5 * std::cos(2 * M_PI * 5 * t.back()));
    }
    const std::string png = dir / "lines.png";
    report::plot_lines({"time series", "time [s]", "displacement [m]"},
                       {{"decaying mode", t, y1, ""}, {"drift", t, y2, "lines lw 1 dt 3"}}, png);
    CHECK(is_png(png));
    CHECK_THROWS_AS(report::plot_lines({}, {{"bad", {1, 2}, {1}, ""}}, png), std::invalid_argument);
    CHECK_THROWS_AS(report::plot_lines({}, {{"inject", t, y1, "lines; system('true')"}}, png),
                    std::invalid_argument);
  }
  SECTION("histogram, log y") {
    std::vector<double> edges, counts;
    for (int i = 0; i <= 60; ++i) edges.push_back(i * 1.0);  // latency [us]
    for (int i = 0; i < 60; ++i)
      counts.push_back(std::floor(1e6 * std::exp(-0.5 * std::pow((i - 8.0) / 2.0, 2)) +
                                  (i > 30 && i % 7 == 0 ? 3.0 : 0.0)));
    const std::string png = dir / "hist.png";
    report::plot_histogram({"wake-up latency", "latency [us]", "cycles", false, true}, edges,
                           counts, png);
    CHECK(is_png(png));
    CHECK_THROWS_AS(report::plot_histogram({}, {0, 1}, {1, 2}, png), std::invalid_argument);
  }
  SECTION("bars with intervals (NaN: no bar), labels with blanks and quotes") {
    const std::string png = dir / "bars.png";
    const double nan = std::nan("");
    report::plot_interval_bars({"Sobol indices", "", "share of the variance"},
                               {"element.\"k\" 1", "mass", "gain"},
                               {{"first", {0.6, 0.3, nan}, {0.5, 0.2, nan}, {0.7, 0.4, nan}},
                                {"total", {0.7, 0.3, 0.05}, {0.6, 0.25, -0.01}, {0.8, 0.35, 0.1}}},
                               png);
    CHECK(is_png(png));
    CHECK_THROWS_AS(report::plot_interval_bars({}, {"a"}, {{"x", {1, 2}, {1}, {1}}}, png),
                    std::invalid_argument);
  }
  // Every section leaves only finished PNGs behind: no scripts, logs or partial images.
  for (const auto& name : dir.files()) CHECK(name.size() > 4);
  for (const auto& name : dir.files()) CHECK(name.substr(name.size() - 4) == ".png");
}

TEST_CASE("plots: missing or failing gnuplot is an error naming the file", "[report][plot]") {
  ScratchDir dir("plot-errors");
  const std::string png = dir / "never.png";
  const report::Series s{"s", {0.0, 1.0}, {1.0, 2.0}, ""};
  REQUIRE(::setenv("FLEXLOOP_GNUPLOT", "/nonexistent/gnuplot", 1) == 0);
  CHECK_THROWS_WITH(report::plot_lines({}, {s}, png),
                    Catch::Contains(png) && Catch::Contains("gnuplot"));
  REQUIRE(::setenv("FLEXLOOP_GNUPLOT", "false", 1) == 0);  // runs, exits with status 1
  CHECK_THROWS_WITH(report::plot_lines({}, {s}, png),
                    Catch::Contains(png) && Catch::Contains("status 1"));
  ::unsetenv("FLEXLOOP_GNUPLOT");
  CHECK(dir.files().empty());
}

namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Pictures of each kind and size, for drawing one at a time and in batches.
std::vector<report::PlotScript> mixed_scripts(const ScratchDir& dir, const std::string& prefix) {
  std::vector<double> t, y;
  for (int i = 0; i <= 200; ++i) t.push_back(i * 1e-2), y.push_back(std::sin(3.0 * t.back()));
  const report::Series line{"sine", t, y, ""};
  report::PlotSpec tall{"stacked", "time [s]", ""};
  tall.height_px = 900;
  return {
      report::lines_script({"lines", "time [s]", "y [m]"}, {line}, dir / (prefix + "lines.png")),
      report::stacked_script(tall, {{"a [m]", {line}}, {"b [m]", {line}}},
                             dir / (prefix + "stacked.png")),
      report::histogram_script({"histogram", "x [s]", "count"}, {0, 1, 2, 3}, {4, 9, 2},
                               dir / (prefix + "histogram.png")),
      report::interval_bars_script({"bars", "", "share"}, {"a", "b"},
                                   {{"first", {0.5, 0.2}, {0.4, 0.1}, {0.6, 0.3}}},
                                   dir / (prefix + "bars.png")),
      report::lines_script({"lines, log x", "time [s]", "y [m]", true}, {line},
                           dir / (prefix + "log.png"))};
}

}  // namespace

std::vector<report::PlotBuilder> builders(const std::vector<report::PlotScript>& scripts) {
  std::vector<report::PlotBuilder> out;
  for (const auto& script : scripts) out.emplace_back([script] { return script; });
  return out;
}

TEST_CASE("plots: a batch in a few gnuplot processes draws the bytes of one process a picture",
          "[report][plot]") {
  ScratchDir dir("plot-batch");
  for (const auto& one : mixed_scripts(dir, "alone_")) report::draw_plots(builders({one}), 1);
  for (int processes : {1, 2, 7}) {
    const std::string prefix = "batch" + std::to_string(processes) + "_";
    std::vector<report::PlotBuilder> batch = builders(mixed_scripts(dir, prefix));
    batch.insert(batch.begin() + 2, [] { return std::optional<report::PlotScript>(); });
    CHECK(report::draw_plots(batch, processes) ==
          std::vector<bool>{true, true, false, true, true, true});
    for (const char* name : {"lines.png", "stacked.png", "histogram.png", "bars.png", "log.png"}) {
      INFO(prefix << name);
      CHECK(is_png(dir / (prefix + name)));
      CHECK(file_bytes(dir / (prefix + name)) == file_bytes(dir / (std::string("alone_") + name)));
    }
  }
  for (const auto& name : dir.files()) CHECK(name.substr(name.size() - 4) == ".png");
}

TEST_CASE("plots: a failing picture in a batch is the error, the others are drawn",
          "[report][plot]") {
  for (int processes : {1, 2}) {
    INFO(processes << " gnuplot processes");
    ScratchDir dir("plot-batch-error-" + std::to_string(processes));
    std::vector<report::PlotScript> scripts = mixed_scripts(dir, "");
    // gnuplot stops at "undefined function" inside a multiplot: the next picture of the same
    // process must not be drawn into it.
    scripts[1].body = "set multiplot layout 2,1\nplot sin(x)\nplot no_such_function(x)\n";
    CHECK_THROWS_WITH(report::draw_plots(builders(scripts), processes),
                      Catch::Contains(dir / "stacked.png") && Catch::Contains("no_such_function"));
    CHECK_FALSE(fs::exists(dir / "stacked.png"));
    for (const char* name : {"lines.png", "histogram.png", "bars.png", "log.png"}) {
      INFO(name);
      CHECK(is_png(dir / name));
    }
    for (const auto& name : dir.files()) CHECK(name.substr(name.size() - 4) == ".png");
  }
  CHECK(report::draw_plots({}, 2).empty());
}
