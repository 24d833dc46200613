// SPDX-License-Identifier: BSD-3-Clause
// JSON artefacts: bit-exact round trips, atomic writes, and bad files reported with their place.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>

#include "common/input_error.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tests/discretise/reference.hpp"

using namespace flexloop::plant::lti;
using namespace flexloop::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    static int counter = 0;
    path = fs::temp_directory_path() / ("flexloop_test_discretise_" + std::to_string(::getpid()) +
                                        "_" + std::to_string(counter++));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return path / name;
  }
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path)) out.push_back(e.path().filename().string());
    return out;
  }
};

// Bit-exact: the same bits, so -0.0 and 0.0 differ and NaN never sneaks through.
bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  return a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Awkward doubles: shortest round-trip printing must still give back the exact bits.
Eigen::MatrixXd awkward(std::mt19937& rng, Eigen::Index r, Eigen::Index c) {
  Eigen::MatrixXd m = random_matrix(rng, r, c);
  std::uniform_real_distribution<double> e(-30, 30);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] *= std::pow(10.0, e(rng));
  const double specials[] = {
      -0.0,      1.0 / 3.0,          1e-300, -4.9e-324, 1.7976931348623157e308, 0.1,
      2.0 / 3.0, 123456789.123456789};
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(m.size(), 8); ++i) m.data()[i] = specials[i];
  return m;
}

// The InputError a read gives, as "place" and "what".
std::pair<std::string, std::string> read_error(const fs::path& file, bool discrete = false) {
  try {
    if (discrete)
      read_discrete(file);
    else
      read_continuous(file);
  } catch (const flexloop::common::InputError& e) {
    return {e.place(), e.what()};
  }
  return {"(no error)", ""};
}

const char* kGood = R"({
  "states": ["x1", "x2"], "inputs": ["u"], "outputs": ["y"],
  "A": [[0, 1], [-4, -0.4]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]]
})";

}  // namespace

TEST_CASE("continuous state space: JSON round trip is bit-exact, provenance passes through") {
  TempDir dir;
  std::mt19937 rng(1);
  const auto sys =
      labelled(awkward(rng, 5, 5), awkward(rng, 5, 3), awkward(rng, 4, 5), awkward(rng, 4, 3));
  const nlohmann::json prov = {{"source", "model.toml"}, {"sha256", "ab12"}, {"n", 3}};
  const auto file = dir.path / "plant.json";
  write_continuous(file, sys, prov);
  const auto back = read_continuous(file);
  CHECK(same_bits(back.sys.A, sys.A));
  CHECK(same_bits(back.sys.B, sys.B));
  CHECK(same_bits(back.sys.C, sys.C));
  CHECK(same_bits(back.sys.D, sys.D));
  CHECK(back.sys.states == sys.states);
  CHECK(back.sys.inputs == sys.inputs);
  CHECK(back.sys.outputs == sys.outputs);
  CHECK(back.provenance == prov);
  CHECK(dir.entries() == std::vector<std::string>{"plant.json"});  // no temporary left behind
}

TEST_CASE("discrete state space: JSON round trip is bit-exact with method, dt and provenance") {
  TempDir dir;
  const auto sys = make_modal_system(4);
  const auto d = discretise(
      sys.ss, {.method = DiscretisationMethod::kTustin, .dt = 1.0 / 3000, .prewarp_hz = 140});
  const nlohmann::json prov = {{"source", "plant.json"}, {"flexloop_version", "0.1.0"}};
  const auto file = dir.path / "plant_d.json";
  write_discrete(file, d, prov);
  const auto back = read_discrete(file);
  CHECK(same_bits(back.sys.sys.A, d.sys.A));
  CHECK(same_bits(back.sys.sys.B, d.sys.B));
  CHECK(same_bits(back.sys.sys.C, d.sys.C));
  CHECK(same_bits(back.sys.sys.D, d.sys.D));
  CHECK(same_bits(back.sys.dt, d.dt));
  CHECK(same_bits(back.sys.prewarp_hz, d.prewarp_hz));
  CHECK(same_bits(back.sys.spectral_radius, d.spectral_radius));
  CHECK(back.sys.method == DiscretisationMethod::kTustin);
  CHECK(back.sys.sys.states == d.sys.states);
  CHECK(back.provenance == prov);

  // The file names its keys as the artefact contract says.
  const auto j = nlohmann::json::parse(std::ifstream(file));
  for (const char* key : {"Ad", "Bd", "Cd", "Dd", "dt", "method", "prewarp_hz", "spectral_radius",
                          "states", "inputs", "outputs", "provenance"})
    CHECK(j.contains(key));
  CHECK(j.at("method") == "tustin");

  // Overwriting replaces the file whole.
  const auto z = discretise(sys.ss, {.method = DiscretisationMethod::kZeroOrderHold, .dt = 1e-3});
  write_discrete(file, z);
  const auto again = read_discrete(file);
  CHECK(again.sys.method == DiscretisationMethod::kZeroOrderHold);
  CHECK(same_bits(again.sys.sys.A, z.sys.A));
  CHECK(again.provenance.is_null());
  CHECK(dir.entries() == std::vector<std::string>{"plant_d.json"});
}

TEST_CASE("a system JSON cannot hold is refused before anything is written") {
  TempDir dir;
  auto sys = continuous_from_json(nlohmann::json::parse(kGood), "good").sys;
  sys.A(1, 0) = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(write_continuous(dir.path / "x.json", sys), std::invalid_argument);
  CHECK(dir.entries().empty());
  CHECK_THROWS_AS(write_continuous(dir.path / "missing_dir" / "x.json",
                                   continuous_from_json(nlohmann::json::parse(kGood), "g").sys),
                  std::runtime_error);
}

TEST_CASE("bad continuous files give flexloop::common::InputError with the place") {
  TempDir dir;
  const std::string f = (dir.path / "p.json").string();
  struct Case {
    const char* name;
    std::string text;
    std::string place;
    const char* what;
  };
  auto good = nlohmann::json::parse(kGood);
  auto edit = [&](auto fn) {
    auto j = good;
    fn(j);
    return j.dump();
  };
  const Case cases[] = {
      {"ragged row", edit([](auto& j) { j["A"][1] = {-4}; }), f + ": key 'A' row 2",
       "has 1 entries, expected 2 (one per state)"},
      {"missing key", edit([](auto& j) { j.erase("C"); }), f + ": key 'C'", "is missing"},
      {"missing labels", edit([](auto& j) { j.erase("states"); }), f + ": key 'states'",
       "is missing"},
      {"wrong rows", edit([](auto& j) {
         j["B"] = {{0}, {1}, {2}};
       }),
       f + ": key 'B'", "has 3 rows, expected 2 (one per state)"},
      {"wrong columns", edit([](auto& j) {
         j["D"] = {{0, 1}};
       }),
       f + ": key 'D' row 1", "has 2 entries, expected 1 (one per input)"},
      {"string for number", edit([](auto& j) { j["A"][0][1] = "1.0"; }),
       f + ": key 'A' row 1 column 2", "expected a number, found string \"1.0\""},
      {"null for number", edit([](auto& j) { j["C"][0][0] = nullptr; }),
       f + ": key 'C' row 1 column 1", "expected a number, found null"},
      {"bool for number", edit([](auto& j) { j["C"][0][1] = true; }),
       f + ": key 'C' row 1 column 2", "expected a number, found boolean"},
      {"row not a list", edit([](auto& j) { j["A"][0] = 3; }), f + ": key 'A' row 1",
       "expected a list of numbers"},
      {"matrix not a list", edit([](auto& j) { j["A"] = "eye"; }), f + ": key 'A'",
       "expected a list of rows"},
      {"label not a string", edit([](auto& j) { j["inputs"][0] = 7; }),
       f + ": key 'inputs' entry 1", "expected a name"},
      {"duplicate label", edit([](auto& j) { j["states"][1] = "x1"; }),
       f + ": key 'states' entry 2", "duplicates the name 'x1'"},
      {"provenance not an object", edit([](auto& j) { j["provenance"] = 3; }),
       f + ": key 'provenance'", "expected an object"},
      {"not JSON", "{\"A\": [[1, 2], [3 4]]}", f, "not valid JSON"},
      {"empty file", "", f, "not valid JSON"},
      {"top-level array", "[1, 2]", f, "expected a JSON object"},
      {"overflowing number",
       std::string(kGood).replace(std::string(kGood).find("[[0, 1]"), 7, "[[1e999, 1]"), f,
       "number overflow"},
  };
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c.name) {
      dir.write("p.json", c.text);
      const auto [place, what] = read_error(f);
      CHECK(place == c.place);
      CHECK_THAT(what, Contains(c.what));
    }
  }
  SECTION("unreadable file") {
    const auto [place, what] = read_error(dir.path / "absent.json");
    CHECK(place == (dir.path / "absent.json").string());
    CHECK_THAT(what, Contains("cannot open"));
  }
  SECTION("the good file reads") {
    dir.write("p.json", kGood);
    CHECK(read_continuous(f).sys.nx() == 2);
  }
}

TEST_CASE("bad discrete files give flexloop::common::InputError with the place") {
  TempDir dir;
  const std::string f = (dir.path / "d.json").string();
  const auto sys = continuous_from_json(nlohmann::json::parse(kGood), "good").sys;
  const auto good =
      to_json(discretise(sys, {.method = DiscretisationMethod::kZeroOrderHold, .dt = 1e-2}));
  struct Case {
    const char* name;
    std::function<void(nlohmann::json&)> edit;
    std::string place;
    const char* what;
  };
  const Case cases[] = {
      {"unknown method", [](auto& j) { j["method"] = "rk4"; }, f + ": key 'method'",
       "valid: zoh, foh, tustin, euler, backward-euler"},
      {"method not a string", [](auto& j) { j["method"] = 1; }, f + ": key 'method'",
       "expected a string"},
      {"negative dt", [](auto& j) { j["dt"] = -0.01; }, f + ": key 'dt'", "must be > 0"},
      {"dt as string", [](auto& j) { j["dt"] = "0.01"; }, f + ": key 'dt'", "expected a number"},
      {"missing spectral radius", [](auto& j) { j.erase("spectral_radius"); },
       f + ": key 'spectral_radius'", "is missing"},
      {"edited Ad", [](auto& j) { j["Ad"][0][0] = 1.5; }, f + ": key 'spectral_radius'",
       "the file was edited or corrupted"},
      {"continuous keys instead of discrete",
       [](auto& j) {
         j["A"] = j["Ad"];
         j.erase("Ad");
       },
       f + ": key 'Ad'", "is missing"},
      {"ragged Bd",
       [](auto& j) {
         j["Bd"][0] = {1, 2};
       },
       f + ": key 'Bd' row 1", "has 2 entries, expected 1 (one per input)"},
  };
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c.name) {
      auto j = good;
      c.edit(j);
      dir.write("d.json", j.dump());
      const auto [place, what] = read_error(f, true);
      CHECK(place == c.place);
      CHECK_THAT(what, Contains(c.what));
    }
  }
}
