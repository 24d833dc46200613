// SPDX-License-Identifier: BSD-3-Clause
// The campaign report (offline/campaign/campaign_report.hpp) on synthetic plans and samples made
// here with known values: the summary's counts, P(unstable), quantiles and Sobol indices against
// numbers computed by hand or by SciPy, and the files it writes.
#include <unistd.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "offline/campaign/campaign_report.hpp"
#include "offline/campaign/column_spill.hpp"
#include "offline/campaign/designs.hpp"
#include "offline/campaign/statistics.hpp"
#include "tests/campaign/reference.hpp"

using namespace flexloop::campaign;
using nlohmann::json;

namespace {

// 100 evaluations: i % 10 == 3 unstable (10), i % 25 == 7 refused (4), i == 50 an error; the
// other 85 stable, with figures that are simple functions of i.
json synthetic_sample(long i) {
  json s{
      {"plan_id", "synthetic"},
      {"index", i},
      {"parameters", {{"element.k.stiffness", 600.0 + 4.0 * i}, {"node.m.mass", 1.0 + 0.01 * i}}}};
  const bool unstable = i % 10 == 3, refused = i % 25 == 7, error = i == 50;
  for (const char* f :
       {"spectral_radius", "natural_frequencies_hz", "rms", "rms_open", "disk_margin_db",
        "disk_margin_deg", "disk_margin_all_db", "disk_margin_all_deg", "peak_sigma", "sigma_max"})
    s[f] = nullptr;
  if (refused || error) {
    s["status"] = refused ? "refused: buckling under preload" : "error: synthetic";
    return s;
  }
  const double x = static_cast<double>(i);
  s["status"] = unstable ? "unstable" : "stable";
  s["spectral_radius"] = unstable ? 1.2 : 0.5 + x / 1000.0;
  s["natural_frequencies_hz"] = {x + 1.0, 2.0 * x + 100.0};
  if (unstable) return s;
  s["rms"] = {{"x", x / 10.0}};
  s["rms_open"] = {{"x", 1.0}};
  s["disk_margin_db"] = 6.0 + 0.01 * x;
  s["disk_margin_deg"] = 40.0 - 0.1 * x;
  s["disk_margin_all_db"] = 5.0 + 0.01 * x;
  s["disk_margin_all_deg"] = 35.0 - 0.1 * x;
  s["peak_sigma"] = x;
  s["sigma_max"] = {x / 100.0 + 0.01, x / 50.0 + 0.01, x / 200.0 + 0.01};
  return s;
}

json synthetic_plan(const char* design, long n, long evaluations) {
  return {{"format", "flexloop-campaign-plan"},
          {"version", 1},
          {"plan_id", "synthetic"},
          {"design", design},
          {"n", n},
          {"evaluations", evaluations},
          {"columns", {"element.k.stiffness", "node.m.mass"}},
          {"sigma_grid_hz", {1.0, 10.0, 100.0}},
          {"nominal", {{"sigma_max", {0.3, 0.9, 0.2}}}}};
}

// A new directory for a report, removed at the end of the test unless FLEXLOOP_KEEP_TEST_OUTPUT
// is set (to look at the pictures).
struct ReportDir {
  std::filesystem::path path;
  explicit ReportDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
  }
  ~ReportDir() {
    if (!std::getenv("FLEXLOOP_KEEP_TEST_OUTPUT")) std::filesystem::remove_all(path);
  }
};

bool is_png(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in && std::string(sig, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}

}  // namespace

TEST_CASE("the summary of a synthetic campaign holds the numbers computed by hand",
          "[campaign][report]") {
  std::vector<json> samples;
  for (long i = 0; i < 100; ++i) samples.push_back(synthetic_sample(i));
  const json summary = campaign_summary(synthetic_plan("random", 100, 100), samples);

  CHECK(summary["counts"] == json{{"total", 100},
                                  {"stable", 85},
                                  {"unstable", 10},
                                  {"marginal", 0},
                                  {"refused", 4},
                                  {"error", 1}});
  // P(unstable) over stable + unstable only (refused and error never count), Clopper-Pearson
  // by SciPy's beta quantiles.
  const json scipy = test::outside_reference(
      {{"task", "clopper_pearson"}, {"cases", {{10, 95, 0.95}, {2, 15, 0.95}}}});
  const json& p = summary["p_unstable"];
  CHECK(p["unstable"] == 10);
  CHECK(p["judged"] == 95);
  CHECK(p["estimate"].get<double>() == Approx(10.0 / 95.0));
  CHECK(p["lo"].get<double>() == Approx(scipy[0]["lo"].get<double>()).epsilon(1e-10));
  CHECK(p["hi"].get<double>() == Approx(scipy[0]["hi"].get<double>()).epsilon(1e-10));
  // Its convergence at n = 1, 2, 4, ..., 64, 100; the first 16 evaluations: 3 and 13 unstable,
  // 7 refused, so 2 of 15.
  const json& conv = summary["p_unstable_convergence"];
  REQUIRE(conv.size() == 8);
  CHECK(conv[4]["n"] == 16);
  CHECK(conv[4]["unstable"] == 2);
  CHECK(conv[4]["judged"] == 15);
  CHECK(conv[4]["hi"].get<double>() == Approx(scipy[1]["hi"].get<double>()).epsilon(1e-10));
  CHECK(conv.back()["n"] == 100);
  // P(not stable): unstable, refused and failed machines over all of them, 15 of 100.
  const json scipy_all =
      test::outside_reference({{"task", "clopper_pearson"}, {"cases", {{15, 100, 0.95}}}});
  const json& q = summary["p_not_stable"];
  CHECK(q["not_stable"] == 15);
  CHECK(q["samples"] == 100);
  CHECK(q["method"] == "clopper-pearson");
  CHECK(q["lo"].get<double>() == Approx(scipy_all[0]["lo"].get<double>()).epsilon(1e-10));
  CHECK(q["hi"].get<double>() == Approx(scipy_all[0]["hi"].get<double>()).epsilon(1e-10));
  CHECK(summary["machines"]["count"] == 100);

  // The first natural frequency of the judged machines (stable and unstable: the passive
  // machine's, which every judged machine has) is i + 1: its quantiles are order statistics of
  // those values, at the ranks SciPy's binomial gives for n = 95.
  std::vector<double> stable;
  for (long i = 0; i < 100; ++i)
    if (samples[static_cast<std::size_t>(i)]["status"] == "stable" ||
        samples[static_cast<std::size_t>(i)]["status"] == "unstable")
      stable.push_back(i + 1.0);
  REQUIRE(stable.size() == 95);
  const json ranks =
      test::outside_reference({{"task", "quantile_ranks"},
                               {"cases", {{95, 0.05, 0.95}, {95, 0.5, 0.95}, {95, 0.95, 0.95}}}});
  const json& f1 = summary["figures"]["natural_frequency_1_hz"];
  CHECK(f1["n"] == 95);
  CHECK(f1["unit"] == "Hz");
  CHECK(f1["population"] == "judged machines (stable, unstable, marginal)");
  CHECK(f1["min"] == 1.0);
  CHECK(f1["max"] == 100.0);
  for (std::size_t k = 0; k < 3; ++k) {
    const json& q = f1["quantiles"][k];
    const double prob = q["p"].get<double>();
    const auto rank = static_cast<std::size_t>(std::ceil(95 * prob));
    CHECK(q["estimate"].get<double>() == stable[rank - 1]);
    const long l = ranks[k]["lo_rank"], u = ranks[k]["hi_rank"];
    if (l >= 1)
      CHECK(q["lo"].get<double>() == stable[static_cast<std::size_t>(l - 1)]);
    else
      CHECK(q["lo"].is_null());
    if (u <= 95)
      CHECK(q["hi"].get<double>() == stable[static_cast<std::size_t>(u - 1)]);
    else
      CHECK(q["hi"].is_null());
  }
  // Every figure is there, each over its population: the spectral radius and the natural
  // frequencies over the judged machines (the unstable ones' radius 1.2 included, not cut at 1),
  // the closed loop's figures over the stable ones (the synthetic unstable samples carry no
  // open-loop RMS).
  for (const char* name : {"spectral_radius", "natural_frequency_2_hz"})
    CHECK(summary["figures"][name]["n"] == 95);
  for (const char* name : {"rms.x", "rms_open.x", "disk_margin_db", "disk_margin_deg",
                           "disk_margin_all_db", "disk_margin_all_deg", "peak_sigma"})
    CHECK(summary["figures"][name]["n"] == 85);
  CHECK(summary["figures"]["spectral_radius"]["max"].get<double>() == 1.2);
  CHECK(summary["figures"]["rms.x"]["population"] == "stable machines");
  CHECK(summary["figures"]["disk_margin_db"]["unit"] == "dB");
  CHECK(summary["figure_order"] == json{"spectral_radius", "natural_frequency_1_hz",
                                        "natural_frequency_2_hz", "rms.x", "rms_open.x",
                                        "disk_margin_db", "disk_margin_deg", "disk_margin_all_db",
                                        "disk_margin_all_deg", "peak_sigma"});
  CHECK_FALSE(summary.contains("sobol"));
}

TEST_CASE("a Saltelli campaign's summary has the Sobol indices of each figure",
          "[campaign][report]") {
  // peak_sigma = 2 u1 + u2 of the unit point: S1 = T1 = 4/5, S2 = T2 = 1/5 (variances 4/12 and
  // 1/12); one refused evaluation drops its base row.
  const long n = 256;
  const int d = 2;
  const long evaluations = evaluation_count(DesignKind::kSaltelli, n, d);
  std::vector<json> samples;
  std::vector<double> y;
  for (long i = 0; i < evaluations; ++i) {
    const std::vector<double> u = unit_point(DesignKind::kSaltelli, n, d, 9, i);
    json s{{"index", i},
           {"status", i == 5 * (d + 2) + 1 ? "refused: synthetic" : "stable"},
           {"parameters", {{"element.k.stiffness", u[0]}, {"node.m.mass", u[1]}}},
           {"peak_sigma", 2 * u[0] + u[1]}};
    if (i == 5 * (d + 2) + 1)
      s["peak_sigma"] = nullptr;
    else if (i / (d + 2) != 5)
      y.push_back(2 * u[0] + u[1]);
    samples.push_back(s);
  }
  const json summary = campaign_summary(synthetic_plan("saltelli", n, evaluations), samples);
  const json& sobol = summary["sobol"]["peak_sigma"];
  CHECK(sobol["base_rows"] == n - 1);
  CHECK(sobol["dropped_rows"] == 1);
  const std::vector<SobolIndex> direct = sobol_indices(y, n - 1, d, 500, 1);
  const double exact[] = {0.8, 0.2};
  for (std::size_t i = 0; i < 2; ++i) {
    const json& p = sobol["parameters"][i];
    CHECK(p["path"] == (i == 0 ? "element.k.stiffness" : "node.m.mass"));
    CHECK(p["first"]["estimate"].get<double>() == direct[i].first.estimate);
    CHECK(p["total"]["hi"].get<double>() == direct[i].total.hi);
    CHECK(p["first"]["estimate"].get<double>() == Approx(exact[i]).margin(0.02));
    CHECK(p["total"]["estimate"].get<double>() == Approx(exact[i]).margin(0.02));
    CHECK(p["first"]["holds_zero"] == false);
  }
}

TEST_CASE("a Saltelli campaign's P(unstable) and quantiles count its independent machines only",
          "[campaign][report]") {
  // Issue 54: n = 8 blocks of d + 2 = 4 evaluations (A, B, A_B^1, A_B^2). Block 0 is unstable
  // throughout (its A_B^i rows are its A machine with one parameter changed), block 1's B row is
  // refused. Independent machines: the 16 A and B rows; 2 unstable of 15 judged, 3 of 16 not
  // stable. Pooling all 32 evaluations said 4 of 31.
  const long n = 8;
  const int d = 2;
  const long evaluations = evaluation_count(DesignKind::kSaltelli, n, d);
  std::vector<json> samples;
  std::vector<double> stable_machines;
  for (long i = 0; i < evaluations; ++i) {
    const long block = i / (d + 2), row = i % (d + 2);
    const bool refused = block == 1 && row == 1, unstable = block == 0;
    json s{{"index", i},
           {"status", refused    ? "refused: synthetic"
                      : unstable ? "unstable"
                                 : "stable"},
           {"parameters", {{"element.k.stiffness", 1.0}, {"node.m.mass", 1.0}}},
           {"peak_sigma", refused || unstable ? json(nullptr) : json(static_cast<double>(i))}};
    if (!refused && !unstable && row < 2) stable_machines.push_back(static_cast<double>(i));
    samples.push_back(s);
  }
  const json summary = campaign_summary(synthetic_plan("saltelli", n, evaluations), samples);
  CHECK(summary["counts"]["total"] == evaluations);
  CHECK(summary["machines"]["count"] == 16);
  const json& p = summary["p_unstable"];
  CHECK(p["unstable"] == 2);
  CHECK(p["judged"] == 15);
  CHECK(p["samples"] == 16);
  CHECK(p["method"] == "clopper-pearson");
  const json scipy = test::outside_reference(
      {{"task", "clopper_pearson"}, {"cases", {{2, 15, 0.95}, {3, 16, 0.95}}}});
  CHECK(p["hi"].get<double>() == Approx(scipy[0]["hi"].get<double>()).epsilon(1e-10));
  const json& q = summary["p_not_stable"];
  CHECK(q["not_stable"] == 3);
  CHECK(q["samples"] == 16);
  CHECK(q["hi"].get<double>() == Approx(scipy[1]["hi"].get<double>()).epsilon(1e-10));
  CHECK(summary["p_unstable_convergence"].back()["n"] == 16);
  // A figure's quantiles: over the 13 stable A and B rows, not the A_B^i rows beside them.
  const json& f = summary["figures"]["peak_sigma"];
  CHECK(f["n"] == 13);
  CHECK(f["max"].get<double>() == stable_machines.back());
  // The Sobol indices still use every block whose evaluations all have the figure.
  CHECK(summary["sobol"]["peak_sigma"]["base_rows"] == n - 2);
}

TEST_CASE("each figure over its population: +inf margins kept, marginal loops their own status",
          "[campaign][report]") {
  // Issue 54, part 1.4. Ten machines: 0..5 stable (disk margin i dB, machine 5's unbounded:
  // "+inf"), 6 and 7 unstable (radius 1.2, 1.3), 8 marginal (no stationary state), 9 refused.
  std::vector<json> samples;
  for (long i = 0; i < 10; ++i) {
    json s{{"index", i}, {"parameters", {{"element.k.stiffness", 1.0}, {"node.m.mass", 1.0}}}};
    const double x = static_cast<double>(i);
    if (i == 9) {
      s["status"] = "refused: buckling under preload";
    } else {
      s["status"] = i <= 5 ? "stable" : i <= 7 ? "unstable" : "marginal: no stationary state";
      s["spectral_radius"] = i <= 5 ? 0.5 + 0.01 * x : i == 6 ? 1.2 : i == 7 ? 1.3 : 1.0;
      s["natural_frequencies_hz"] = {x + 1.0};
      s["rms_open"] = {{"acc:y.1", 2 * x}};
    }
    if (i <= 5) {
      s["rms"] = {{"acc:y.1", x}};
      s["disk_margin_db"] = i == 5 ? json("+inf") : json(x);
    }
    if (i == 8) s["disk_margin_db"] = 3.0;
    samples.push_back(s);
  }
  const json summary = campaign_summary(synthetic_plan("random", 10, 10), samples);
  CHECK(summary["counts"]["marginal"] == 1);
  CHECK(summary["p_unstable"]["unstable"] == 2);
  CHECK(summary["p_unstable"]["judged"] == 9);  // the marginal machine is judged, not unstable
  CHECK(summary["p_not_stable"]["not_stable"] == 4);
  const json& f = summary["figures"];
  CHECK(f["spectral_radius"]["n"] == 9);
  CHECK(f["spectral_radius"]["max"] == 1.3);
  CHECK(f["natural_frequency_1_hz"]["n"] == 9);
  CHECK(f["rms_open.acc:y.1"]["n"] == 9);
  CHECK(f["rms_open.acc:y.1"]["unit"] == "m/s^2");
  CHECK(f["rms.acc:y.1"]["n"] == 6);
  // The unbounded margin is the best machine, kept in the order statistics: the maximum and
  // the 95 % quantile's estimate (rank ceil(6 * 0.95) = 6 of 6) are +inf; the marginal
  // machine's 3 dB is not among the stable ones.
  CHECK(f["disk_margin_db"]["n"] == 6);
  CHECK(f["disk_margin_db"]["max"] == "+inf");
  CHECK(f["disk_margin_db"]["min"] == 0.0);
  CHECK(f["disk_margin_db"]["quantiles"][2]["estimate"] == "+inf");
  CHECK(f["disk_margin_db"]["quantiles"][1]["estimate"] == 2.0);  // rank ceil(6 * 0.5) = 3
  // The report: the marginal column, P(not stable), +inf in the table, and no unstable
  // machine in the ECDF of a closed-loop figure.
  const ReportDir report("flexloop_campaign_populations");
  write_campaign_report(synthetic_plan("random", 10, 10), samples, report.path.string());
  std::ifstream md_in(report.path / "report.md");
  const std::string md((std::istreambuf_iterator<char>(md_in)), std::istreambuf_iterator<char>());
  CHECK(md.find("| 10 | 6 | 2 | 1 | 1 | 0 |") != std::string::npos);
  CHECK(md.find("4 of 10 machines unstable, marginal, refused or failed") != std::string::npos);
  CHECK(md.find("| disk_margin_db [dB] | stable | 6 |") != std::string::npos);
  CHECK(md.find("+inf [") != std::string::npos);
  CHECK(is_png(report.path / "ecdf_disk_margin_db.png"));
}

TEST_CASE("with no unstable machine the report says the interval is one-sided",
          "[campaign][report]") {
  std::vector<json> samples;
  for (long i = 0; i < 100; ++i) {
    json s = synthetic_sample(i);
    if (s["status"] == "unstable") s["status"] = "stable";
    samples.push_back(s);
  }
  const json summary = campaign_summary(synthetic_plan("random", 100, 100), samples);
  CHECK(summary["p_unstable"]["lo"] == 0.0);
  const ReportDir report("flexloop_campaign_zero_failures");
  write_campaign_report(synthetic_plan("random", 100, 100), samples, report.path.string());
  std::ifstream md_in(report.path / "report.md");
  const std::string md((std::istreambuf_iterator<char>(md_in)), std::istreambuf_iterator<char>());
  // 95 judged, none unstable: the one-sided 95 % bound 1 - 0.05^(1/95) = 0.03104.
  CHECK(md.find("interval is one-sided") != std::string::npos);
  CHECK(md.find("1 - 0.05^(1/95) = 0.03104") != std::string::npos);
}

TEST_CASE("the report writes summary.json, report.md and valid PNG pictures",
          "[campaign][report]") {
  std::vector<json> samples;
  for (long i = 0; i < 100; ++i) samples.push_back(synthetic_sample(i));
  const ReportDir report("flexloop_campaign_report");
  const auto& dir = report.path;
  write_campaign_report(synthetic_plan("random", 100, 100), samples, dir.string());
  std::ifstream in(dir / "summary.json");
  const json summary = json::parse(in);
  CHECK(summary["counts"]["stable"] == 85);
  std::ifstream md_in(dir / "report.md");
  const std::string md((std::istreambuf_iterator<char>(md_in)), std::istreambuf_iterator<char>());
  CHECK(md.find("| natural_frequency_1_hz [Hz] | judged | 95 |") != std::string::npos);
  CHECK(md.find("| rms.x [N] | stable | 85 |") != std::string::npos);
  CHECK(md.find("10 unstable of 95 judged") != std::string::npos);
  CHECK(md.find("**P(not stable)** = 0.15") != std::string::npos);
  CHECK(md.find("independent machines: the intervals hold as stated") != std::string::npos);
  for (const char* png :
       {"p_unstable.png", "ecdf_natural_frequency_1_hz.png", "ecdf_rms.x.png",
        "ecdf_rms_open.x.png", "histogram_natural_frequency_1_hz.png", "sigma_envelope.png",
        "scatter_element.k.stiffness.png", "scatter_node.m.mass.png"}) {
    INFO(png);
    CHECK(is_png(dir / png));
    CHECK(std::filesystem::file_size(dir / png) > 5000);
    CHECK(md.find(std::string("](") + png + ")") != std::string::npos);
  }
  // No temporary file left beside the pictures.
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    CHECK((ext == ".png" || ext == ".json" || ext == ".md"));
  }
}

TEST_CASE("a Saltelli report draws the Sobol bars", "[campaign][report]") {
  const long n = 64;
  const int d = 2;
  const long evaluations = evaluation_count(DesignKind::kSaltelli, n, d);
  std::vector<json> samples;
  for (long i = 0; i < evaluations; ++i) {
    const std::vector<double> u = unit_point(DesignKind::kSaltelli, n, d, 9, i);
    samples.push_back({{"index", i},
                       {"status", "stable"},
                       {"parameters", {{"element.k.stiffness", u[0]}, {"node.m.mass", u[1]}}},
                       {"spectral_radius", 0.5 + 0.1 * u[0] * u[1]},
                       {"peak_sigma", 2 * u[0] + u[1]}});
  }
  const ReportDir report("flexloop_campaign_sobol_report");
  const auto& dir = report.path;
  write_campaign_report(synthetic_plan("saltelli", n, evaluations), samples, dir.string());
  CHECK(is_png(dir / "sobol_peak_sigma.png"));
  CHECK(std::filesystem::file_size(dir / "sobol_peak_sigma.png") > 5000);
}

TEST_CASE("a report refuses samples that do not fit the plan", "[campaign][report]") {
  std::vector<json> samples;
  for (long i = 0; i < 10; ++i) samples.push_back(synthetic_sample(i));
  CHECK_THROWS_AS(campaign_summary(synthetic_plan("random", 11, 11), samples),
                  std::invalid_argument);
  std::swap(samples[2], samples[3]);
  CHECK_THROWS_AS(campaign_summary(synthetic_plan("random", 10, 10), samples),
                  std::invalid_argument);
}

TEST_CASE("columns spilled to their file read back as pushed, interleaved and in any number",
          "[campaign][report]") {
  // Issue 54, 2.5: the σ curves of 10^6 machines are kept in a file, a chunk per column in memory.
  ColumnSpill spill(3);
  std::vector<std::vector<double>> expected(3);
  for (long i = 0; i < 30000; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      if (c == 2 && i % 3 != 0) continue;  // columns of different lengths
      const double v = std::sin(static_cast<double>(i) + 0.1 * static_cast<double>(c));
      spill.push(c, v);
      expected[c].push_back(v);
    }
  for (std::size_t c = 0; c < 3; ++c) CHECK(spill.column(c) == expected[c]);
  ColumnSpill moved = std::move(spill);
  CHECK(moved.column(1) == expected[1]);
  CHECK(ColumnSpill(2).column(1).empty());
}
