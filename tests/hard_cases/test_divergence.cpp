// Hard case 7, the last line of defence (DESIGN.md §9): a run that diverges although its artefact
// passed the stability checks stops at the first sample where the performance outputs and
// commands leave the stated range (|[z; u]| <= sim::kDivergenceLimit = 1e12, finite), and says
// when and where; `flexloop sim` then exits non-zero and writes nothing.
//
// Reference: the artefact's plant made unstable by hand (Ad scaled by 1.01, every pole 1 % outside
// its place), so the run must diverge, and the sample where it does is bounded by the growth:
// from a state of at least 1e-12 (the floor's motion) to 1e12 at 1.01 per sample takes at most
// ln(1e24) / ln(1.01) = 5554 samples.
#include <catch2/catch.hpp>

#include <cmath>

#include "offline/scene/loop_input.hpp"
#include "online/sim/scene_runs.hpp"

using namespace flexloop;

namespace {

sim::RunResult run_scaled(const std::string& scene, double scale, bool general) {
  auto a = scene::load_loop(scene, {.rate_hz = 0, .form = "dense", .duration_s = 2});
  a.plant.A *= scale;
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(a.duration_s / s.dt);
  sim::SceneRunOptions o;
  o.general = general;
  return sim::run_artefact(a, s, o).off;
}

}  // namespace

TEST_CASE("a diverging run stops at the sample it leaves the range and says where",
          "[hard][divergence]") {
  struct Case {
    const char* scene;
    bool general;
  };
  for (const Case c : {Case{"tools/scenes/metrology_frame.toml", false},
                       Case{"tools/scenes/payload_bipods.toml", true}}) {
    CAPTURE(c.scene);
    const sim::RunResult stable = run_scaled(c.scene, 1.0, c.general);
    CHECK_FALSE(stable.divergence.happened());
    const sim::RunResult r = run_scaled(c.scene, 1.01, c.general);
    const sim::Divergence& d = r.divergence;
    REQUIRE(d.happened());
    WARN(c.scene << ": diverged at sample " << d.step << " (t = " << d.t << " s), "
                 << (d.command ? "command " : "performance output ") << d.channel << " = "
                 << d.value);
    CHECK(d.step > 0);
    CHECK(d.step <= 5554);
    CHECK(d.t == Approx(d.step / 1e4));
    CHECK_FALSE(d.command);  // no controller runs in the off run
    CHECK(std::abs(d.value) > 0);
    // The RMS values cover the samples before it: finite.
    CHECK(r.rms_performance.allFinite());
  }
}
