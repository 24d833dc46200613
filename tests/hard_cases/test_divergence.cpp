// SPDX-License-Identifier: BSD-3-Clause
// Hard case 7, the last line of defence (doc/design.md §9): a run that diverges although its
// artefact passed the stability checks stops at the first sample where the performance outputs and
// commands leave the stated range (|[z; u]| <= plant::runtime::kDivergenceLimit = 1e12, finite),
// and says when and where; `flexloop sim` then exits 1 and writes nothing.
//
// Reference: the artefact's plant made unstable by hand (Ad scaled by 1.01: the run must
// diverge) and the run's own log of every sample (z and u as logged, not the code under test's
// sums): the sample before the reported one is within the range, the reported sample's channel
// and value are the largest there, and the RMS values are those of the samples before it.
#include <catch2/catch.hpp>

#include <cmath>

#include "offline/scene/loop_input.hpp"
#include "online/sim/scene_runs.hpp"

using namespace flexloop;

namespace {

sim::RunResult run_scaled(const std::string& scene, double scale, bool general, long log_every) {
  auto a =
      scene::load_loop(scene, {.rate_hz = 0, .form = artefact::PlantForm::kDense, .duration_s = 2});
  a.plant.A *= scale;
  sim::RunSettings s;
  s.dt = a.dt();
  s.steps = std::lround(a.duration_s / s.dt);
  s.log_every = log_every;
  sim::SceneRunOptions o;
  o.general = general;
  o.log_off = log_every > 0;
  return sim::run_artefact(a, s, o).off;
}

}  // namespace

TEST_CASE("a diverging run stops at the sample it leaves the range and says where",
          "[hard][divergence]") {
  struct Case {
    const char* scene;
    bool general;
    Eigen::Index nw, nz;  // disturbances, performance outputs (the log's columns)
  };
  for (const Case c : {Case{"tools/scenes/metrology_frame.toml", false, 6, 6},
                       Case{"tools/scenes/payload_bipods.toml", true, 6, 8}}) {
    CAPTURE(c.scene);
    CHECK_FALSE(run_scaled(c.scene, 1.0, c.general, 0).divergence.happened());
    const sim::RunResult r = run_scaled(c.scene, 1.01, c.general, 1);
    const sim::Divergence& d = r.divergence;
    REQUIRE(d.happened());
    WARN(c.scene << ": diverged at sample " << d.step << " (t = " << d.t << " s), "
                 << (d.command ? "command " : "performance output ") << d.channel << " = "
                 << d.value);
    REQUIRE(d.step > 0);
    CHECK(d.t == Approx(static_cast<double>(d.step) / 1e4));
    CHECK_FALSE(d.command);  // no controller runs in the off run: the commands are zero
    // The log holds the samples before it; the last of them was within the range.
    REQUIRE(r.log.rows() == d.step);
    const Eigen::MatrixXd z = r.log.matrix().middleCols(1 + c.nw, c.nz);
    const double last = z.row(d.step - 1).norm();
    CHECK(last <= plant::runtime::kDivergenceLimit);
    CHECK(std::abs(d.value) > last / c.nz);  // the largest channel of a vector beyond 1e12
    // RMS over the samples before it, as the log gives them.
    const Eigen::VectorXd rms =
        (z.colwise().squaredNorm() / static_cast<double>(d.step)).cwiseSqrt().transpose();
    CHECK(((r.rms_performance - rms).cwiseAbs().array() <= 1e-12 * rms.array()).all());
  }
}
