// SPDX-License-Identifier: BSD-3-Clause
// The accuracy-vs-time study (offline/study/tradeoff.hpp) on a machine that is not shipped (the
// three-mass fixture under PI force feedback): properties that hold whatever the timing,
//   - ZOH's error in the band falls with the rate, as the hold's half-sample delay does (∝ T);
//   - the balanced reductions' error against the continuous model stays within their a-priori
//     bound, and no reduced order is more accurate in the band than a higher one or the full;
//   - float's errors sit above double's in the time domain (double ZOH at full order is the
//     reference itself);
//   - forward Euler is kept as a row with its reason where it cannot discretise;
//   - the Pareto front is non-dominated and the budget answer is the cheapest row within it;
//   - the CSV, JSON and PNG files are written.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "offline/scene/scene.hpp"
#include "offline/scene/scene_plant.hpp"
#include "offline/study/tradeoff.hpp"
#include "offline/study/tradeoff_report.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/model_reduction.hpp"

using namespace flexloop;

namespace {

const scene::ScenePlant& three_masses() {
  static const scene::ScenePlant p =
      scene::build_scene_plant(scene::load_scene("tests/fixtures/three_masses.toml"));
  return p;
}

study::TradeoffOptions small_sweep() {
  study::TradeoffOptions o;
  o.methods = {"zoh", "tustin", "euler"};
  o.rates_hz = {500, 1000, 2000, 5000, 10000};
  o.forms = {"dense", "modal"};
  o.scalars = {"double", "float"};
  o.reductions = {"balanced", "modal"};
  o.orders = {6, 8};
  o.band_hz = 40;  // the first passive mode (32.9 Hz) in the band, the 87 and 91 Hz pair above
  o.run_s = 0.2;
  o.bench_steps = 2000;
  o.repeats = 3;
  return o;
}

const study::TradeoffResult& sweep() {
  static const study::TradeoffResult r = study::run_tradeoff(three_masses(), small_sweep());
  return r;
}

const study::Measurement& row(const std::string& method, double rate, const std::string& form,
                              const std::string& scalar, const std::string& reduction, int order) {
  for (const auto& m : sweep().rows) {
    const auto& c = m.config;
    if (c.method_name() == method && c.rate_hz == rate && artefact::to_string(c.form) == form &&
        to_string(c.scalar) == scalar && to_string(c.reduction) == reduction && c.order == order)
      return m;
  }
  FAIL("no row " << method << " " << rate << " " << form << " " << scalar << " " << reduction << " "
                 << order);
  throw;
}

}  // namespace

// One sweep, computed once per process, serves every property below: each is a section of one test
// case, so that ctest computes the sweep once (as seven test cases, seven processes computed it,
// 5.3 s each under the sanitizers).
TEST_CASE("tradeoff: the three-mass sweep's properties") {
  SECTION("every configuration has a row, measured or with its reason") {
    const auto& r = sweep();
    CHECK(r.full_order == 10);  // 6 of the masses, 4 of the two floor plates (double integrators)
    CHECK(r.rows.size() == 3 * 5 * 2 * 2 * (1 + 2 * 2));
    CHECK(r.default_config.label() == "zoh 5000 Hz dense double full 10");
    for (const auto& m : r.rows) {
      INFO(m.config.label() << ": " << m.skipped);
      if (!m.skipped.empty()) continue;
      CHECK(std::isfinite(m.hinf_error));
      CHECK(m.ns_per_step > 0);
      CHECK(m.ns_min <= m.ns_per_step);
      CHECK(m.ns_per_step <= m.ns_max);
      CHECK(m.period_share == Approx(m.ns_per_step * 1e-9 * m.config.rate_hz));
      CHECK((m.kernel == "general" || m.kernel == "compiled"));
    }
    // Forward Euler turns the lightly damped modes unstable at the low rates: refused, with why.
    const auto& euler = row("euler", 500, "dense", "double", "full", 10);
    CHECK_THAT(euler.skipped, Catch::Contains("euler"));
    // The floor plates' double integrators are Jordan blocks, which the modal form keeps beside the
    // masses' modes: the row is measured.
    CHECK(row("zoh", 1000, "modal", "double", "full", 10).skipped.empty());
  }

  SECTION("ZOH's error in the band falls in proportion to the sample time") {
    double previous = INFINITY, previous_rate = 0;
    for (const double rate : {500.0, 1000.0, 2000.0, 5000.0, 10000.0}) {
      const auto& m = row("zoh", rate, "dense", "double", "full", 10);
      REQUIRE(m.skipped.empty());
      INFO(rate << " Hz: " << m.hinf_error);
      CHECK(m.hinf_error < previous);
      if (previous_rate > 0) {
        // The hold's half-sample delay, e^{-j w T/2}: first order in T.
        const double ratio = previous / m.hinf_error, expected = rate / previous_rate;
        CHECK(ratio == Approx(expected).epsilon(0.25));
      }
      previous = m.hinf_error;
      previous_rate = rate;
      // Exact at the samples for a step, and the reference of the closed loop itself.
      CHECK(m.step_error == 0);
      CHECK(m.closed_loop_error == 0);
      CHECK(std::isnan(m.dc_error));  // the floor plates' poles at the origin: no DC gain
    }
  }

  SECTION(
      "balanced reductions stay within their bound, and a higher order is never less accurate") {
    const auto& p = three_masses();
    const auto f = plant::lti::log_frequency_grid_hz(0.01, 1e4, 3000);
    const auto g = plant::lti::frequency_response(p.plant, f);
    double previous = INFINITY;
    for (const int order : {6, 8}) {
      const auto reduced = plant::lti::balanced_truncation(p.plant, order);
      const auto gr = plant::lti::frequency_response(reduced.sys, f);
      double error = 0;
      for (std::size_t k = 0; k < f.size(); ++k)
        error =
            std::max(error, Eigen::JacobiSVD<Eigen::MatrixXcd>(g[k] - gr[k]).singularValues()(0));
      INFO("order " << order << ": error " << error << ", bound " << reduced.error_bound);
      CHECK(error <= reduced.error_bound * (1 + 1e-9));
      CHECK(error < previous);
      previous = error;
      CHECK(row("zoh", 5000, "dense", "double", "balanced", order).reduction_bound ==
            Approx(reduced.error_bound));
    }
    for (const double rate : {1000.0, 10000.0}) {
      const double e6 = row("zoh", rate, "dense", "double", "balanced", 6).hinf_error;
      const double e8 = row("zoh", rate, "dense", "double", "balanced", 8).hinf_error;
      const double e10 = row("zoh", rate, "dense", "double", "full", 10).hinf_error;
      INFO("balanced at " << rate << " Hz: orders 6, 8, 10: " << e6 << ", " << e8 << ", " << e10);
      CHECK(e8 <= e6);
      CHECK(e10 <= e8);
    }
    // Modal truncation keeps the floor plates' double integrators (Jordan blocks) as one block.
    CHECK(row("zoh", 1000, "dense", "double", "modal", 6).skipped.empty());
  }

  SECTION("float's errors sit above double's") {
    for (const double rate : {1000.0, 10000.0})
      for (const std::string form : {"dense"}) {
        const auto& d = row("zoh", rate, form, "double", "full", 10);
        const auto& s = row("zoh", rate, form, "float", "full", 10);
        INFO(rate << " Hz " << form << ": DC " << d.dc_error << " / " << s.dc_error << ", step "
                  << d.step_error << " / " << s.step_error << ", loop " << d.closed_loop_error
                  << " / " << s.closed_loop_error);
        CHECK(s.step_error > d.step_error);
        CHECK(s.closed_loop_error > d.closed_loop_error);
        CHECK(s.step_error < 1e-3);  // float, not garbage
        // Not the H-inf figure: float's rounding of Ad - I moves the lightly damped poles, and
        // the error against the continuous plant (the hold's delay, at these rates) may grow or
        // shrink by it (0.0104 -> 0.0103 at 10 kHz).
      }
  }

  SECTION("the Pareto front is non-dominated and the budget answer is the cheapest within it") {
    const auto& r = sweep();
    const auto front = study::pareto_front(r);
    REQUIRE(!front.empty());
    for (const std::size_t k : front)
      for (const auto& m : r.rows) {
        if (!m.skipped.empty()) continue;
        const auto& f = r.rows[k];
        CHECK_FALSE((m.ns_per_step <= f.ns_per_step && m.hinf_error <= f.hinf_error &&
                     (m.ns_per_step < f.ns_per_step || m.hinf_error < f.hinf_error)));
      }
    const double budget = 0.05;
    const long best = study::cheapest_within(r, budget);
    REQUIRE(best >= 0);
    const auto& b = r.rows[static_cast<std::size_t>(best)];
    CHECK(b.hinf_error <= budget);
    for (const auto& m : r.rows)
      if (m.skipped.empty() && m.hinf_error <= budget) CHECK(m.ns_per_step >= b.ns_per_step);
    CHECK_THAT(study::budget_answer(r, budget),
               Catch::Contains(b.config.label()) && Catch::Contains("less time per step"));
    CHECK_THAT(study::budget_answer(r, 1e-30), Catch::Contains("no configuration"));
  }

  SECTION("the table, CSV, JSON and the Pareto front PNG") {
    const auto& r = sweep();
    const std::string dir = "build/test-output/tradeoff";
    std::filesystem::create_directories(dir);
    study::write_csv(dir + "/tradeoff.csv", r);
    std::ifstream csv(dir + "/tradeoff.csv");
    std::string header;
    std::getline(csv, header);
    CHECK(header == study::csv_header());
    long lines = 0;
    for (std::string l; std::getline(csv, l);) ++lines;
    CHECK(lines == static_cast<long>(r.rows.size()));
    const nlohmann::json j = study::to_json(r);
    CHECK(j["rows"].size() == r.rows.size());
    CHECK(j["default"]["method"] == "zoh");
    CHECK(j["default"]["rate_hz"] == 5000);
    std::filesystem::remove(dir + "/front.png");
    study::write_front_png(dir + "/front.png", r, "three masses");
    CHECK(std::filesystem::file_size(dir + "/front.png") > 1000);
    std::ostringstream table;
    study::print_table(table, r);
    CHECK_THAT(table.str(), Catch::Contains("ns/step") && Catch::Contains("skipped"));
  }

  SECTION("the front's cost axis spans the costs with a margin, log only beyond a decade") {
    // The sweep: every step between 50 and 90 ns (gnuplot's log axis made it 10 to 100 ns).
    const study::AxisRange narrow = study::cost_axis({52.0, 61.5, 90.0, 50.0, 73.2});
    CHECK_FALSE(narrow.log);
    const double span = 90.0 - 50.0;
    CHECK(narrow.min == Approx(50.0 - study::kCostAxisMargin * span));
    CHECK(narrow.max == Approx(90.0 + study::kCostAxisMargin * span));
    // The data fill most of the axis: their span is 1 / (1 + 2 x margin) of it.
    CHECK(span / (narrow.max - narrow.min) == Approx(1 / (1 + 2 * study::kCostAxisMargin)));
    CHECK(span / (narrow.max - narrow.min) > 0.8);

    // Over more than a decade (the share of the period at rates 10x apart): log, the margin in
    // decades; non-finite and non-positive costs (nothing measured) are left out.
    const study::AxisRange wide =
        study::cost_axis({0.05, 0.4, 2.5, std::numeric_limits<double>::quiet_NaN(), 0.0});
    CHECK(wide.log);
    const double decades = std::log10(2.5 / 0.05);
    CHECK(std::log10(0.05 / wide.min) == Approx(study::kCostAxisMargin * decades));
    CHECK(std::log10(wide.max / 2.5) == Approx(study::kCostAxisMargin * decades));

    // Equal costs: +-10 % around them; a linear axis never goes below zero.
    const study::AxisRange equal = study::cost_axis({40.0, 40.0});
    CHECK(equal.min == Approx(36.0));
    CHECK(equal.max == Approx(44.0));
    CHECK(study::cost_axis({0.1, 1.0}).min >= 0);
    const study::AxisRange none = study::cost_axis({});
    CHECK_FALSE(none.max > none.min);  // nothing measured: gnuplot's own axis

    // The measured sweep: the axis spans every measured row's cost, with the margin at both ends.
    const auto& r = sweep();
    const study::AxisRange axis = study::front_cost_axis(r);
    double lo = 1e300, hi = 0;
    for (const auto& m : r.rows)
      if (m.skipped.empty()) lo = std::min(lo, m.ns_per_step), hi = std::max(hi, m.ns_per_step);
    REQUIRE(hi > lo);
    CHECK(axis.log == (hi > 10 * lo));
    CHECK(axis.min < lo);
    CHECK(axis.max > hi);
    if (!axis.log) {
      CHECK(lo - axis.min <= study::kCostAxisMargin * (hi - lo) * (1 + 1e-9));
      CHECK(axis.max - hi == Approx(study::kCostAxisMargin * (hi - lo)));
    }
  }
}

TEST_CASE("tradeoff: options it cannot take are refused naming them") {
  auto o = small_sweep();
  o.methods = {"rk4"};
  CHECK_THROWS_WITH(study::run_tradeoff(three_masses(), o),
                    Catch::Contains("--methods") && Catch::Contains("rk4"));
  o = small_sweep();
  o.orders = {11};
  CHECK_THROWS_WITH(study::run_tradeoff(three_masses(), o),
                    Catch::Contains("--orders") && Catch::Contains("1 .. 10"));
}
