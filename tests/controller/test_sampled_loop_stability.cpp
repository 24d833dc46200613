// SPDX-License-Identifier: BSD-3-Clause
// Sampled closed-loop stability (issue 17, case 7; controller/design/sampled_loop_stability.hpp).
// A continuous loop that is stable can be unstable as it runs: sampled at the scene's rate, with
// the discrete PI, the held command and the delays. The one-strut fixture (tests/fixtures/
// one_strut_200hz.toml: omega_d = 100 Hz at 200 Hz) is such a loop. The reference here is the
// runtime itself, not the offline loop model under test: the plant sample_scene gives sim
// (DensePlant), the PiController sim runs and SampleDelay for the sensor path, wired by hand and
// stepped from a displaced strut. What the model says (spectral radius) must be what that loop
// does (its growth per sample), and what the refusal suggests must run bounded.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/input_error.hpp"
#include "controller/design/sampled_loop_stability.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "offline/scene/pi_parameters.hpp"
#include "offline/scene/scene_plant.hpp"
#include "plant/lti/feedback_interconnection.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/effects/sample_delay.hpp"

using namespace flexloop;

namespace {

constexpr const char* kOneStrut = "tests/fixtures/one_strut_200hz.toml";

scene::ScenePlant one_strut(double rate_hz = 0, double omega_d_hz = 0, int transport_delay = 0) {
  scene::Scene sc = scene::load_scene(kOneStrut);
  if (rate_hz > 0) sc.discretisation.rate_hz = rate_hz;
  if (omega_d_hz > 0) sc.controller.omega_d_hz = omega_d_hz;
  sc.effects.transport_delay_samples = transport_delay;
  return scene::build_scene_plant(sc);
}

struct RuntimeRun {
  double initial = 0;  ///< |sensor force| + |command| at the first sample [N]
  double largest = 0;  ///< the largest over the run
  double growth = 0;   ///< per sample: the ratio of the last two whole windows' maxima, ^(1/window)
  long steps = 0;      ///< run (stops early once beyond 1e150)
};

// The runtime loop of `flexloop sim` with the floor still: y_k = the plant's force output (with
// the force held since k-1), delayed by `delay` samples, u_k = PI(y_k) (which removes its own
// force `delay` samples late), then the plant advances with u_k. Starts from a strut elongated by
// 1 um. The measure q_k = |y_k| + |u_k| in newtons.
RuntimeRun run_runtime_loop(const scene::ScenePlant& p, long steps, int delay = 0,
                            long window = 20) {
  const auto sampled = scene::sample_scene(p);
  const auto& d = sampled.plant.sys;
  REQUIRE(d.nx() == 2);
  using Plant = plant::runtime::DensePlant<double, 2, 2, 2, 1>;
  Plant plant = Plant::from_matrices(d.A, d.B, d.C, d.D);
  Plant::State x0 = Plant::State::Zero();
  x0(0) = 1e-6;  // zoh keeps the physical state: the elongation first
  plant.set_state(x0);
  artefact::PiParameters pi = scene::pi_parameters(p, sampled.plant.dt);
  pi.feedthrough_delay = delay;
  auto pic = controller::runtime::PiController<double, 1>::from_parameters(pi);
  auto line = plant::runtime::effects::SampleDelay<double, 1>::from_parameters(delay);
  Plant::Input in = Plant::Input::Zero();
  const Eigen::Matrix<double, 1, 1> still = Eigen::Matrix<double, 1, 1>::Zero();
  RuntimeRun r;
  double previous = 0, last = 0, current = 0;  // window maxima
  long k = 0;
  for (; k < steps; ++k) {
    const Plant::Output y = plant.output(still);
    const Eigen::Matrix<double, 1, 1> measured = line.step(y.tail<1>());
    const auto u = pic.step(measured);
    in(1) = u(0);
    plant.advance(in);
    const double q = std::abs(y(1)) + std::abs(u(0));
    if (k == 0) r.initial = q;
    r.largest = std::max(r.largest, q);
    current = std::max(current, q);
    if ((k + 1) % window == 0) previous = last, last = current, current = 0;
    if (!(q < 1e150)) {
      ++k;
      break;
    }
  }
  r.steps = k;
  if (previous > 0) r.growth = std::pow(last / previous, 1.0 / static_cast<double>(window));
  return r;
}

// The spectral radius of the one-step matrix, the code under test.
double radius(const scene::ScenePlant& p) {
  return scene::sampled_loop(p).stability.spectral_radius;
}

}  // namespace

TEST_CASE("sampled loop: the one-strut loop at 200 Hz is stable continuous, unstable sampled",
          "[controller][sampled]") {
  const auto p = one_strut();
  // The trap: the continuous loop is fine, without a leak.
  CHECK(p.loop.stable());
  CHECK(scene::minimum_stable_leak_hz(p) == 0.0);
  const auto s = scene::sampled_loop(p);
  INFO("spectral radius " << s.stability.spectral_radius);
  CHECK_FALSE(s.stability.stable());
  CHECK(s.stability.spectral_radius > 1.5);
  // The runtime loop diverges as fast as the model says: the measured growth per sample equals
  // the spectral radius within 1 %, and 1 um of elongation becomes > 1e150 N.
  const RuntimeRun run = run_runtime_loop(p, 100000);
  INFO("runtime: " << run.steps << " steps, growth " << run.growth << " per sample");
  CHECK(run.largest >= 1e150);
  CHECK(std::abs(run.growth / s.stability.spectral_radius - 1) < 0.01);
}

TEST_CASE(
    "sampled loop: an unstable one is refused before any run, naming a rate and an "
    "omega_d that work",
    "[controller][sampled]") {
  const auto p = one_strut();
  try {
    scene::require_stable_loop(p);
    FAIL("the unstable sampled loop was accepted");
  } catch (const common::InputError& e) {
    const std::string what = e.what();
    INFO(what);
    // At the rate_hz line of the fixture (line 22), with the spectral radius and the remedies.
    CHECK(what.rfind(std::string(kOneStrut) +
                         ":22: [discretisation]: the sampled loop is unstable at 200 Hz (zoh",
                     0) == 0);
    CHECK(what.find("spectral radius") != std::string::npos);
    CHECK(what.find("stable: rate_hz = ") != std::string::npos);
    CHECK(what.find("or omega_d_hz <= ") != std::string::npos);
    CHECK(what.find(std::string(kOneStrut) + ":17)") != std::string::npos);  // omega_d_hz
  }
  const auto remedy = scene::stable_sampled_loop_remedy(p);
  REQUIRE(remedy.rate_hz);
  REQUIRE(remedy.omega_d_hz);
  INFO("rate " << *remedy.rate_hz << " Hz, omega_d " << *remedy.omega_d_hz << " Hz");
  CHECK(*remedy.rate_hz > 200);
  CHECK(*remedy.rate_hz <= 10000);
  CHECK(*remedy.omega_d_hz < 100);
  CHECK(*remedy.omega_d_hz > 10);
}

TEST_CASE(
    "sampled loop: the suggested rate and omega_d run bounded in the runtime loop, just "
    "beyond them it diverges",
    "[controller][sampled]") {
  const auto remedy = scene::stable_sampled_loop_remedy(one_strut());
  REQUIRE(remedy.rate_hz);
  REQUIRE(remedy.omega_d_hz);
  // Bounded: over 1e5 samples no force exceeds 10 x the first sample's (the pure integrator's
  // pole at z = 1 is marginal: the loop settles, it does not return to zero by itself).
  for (const auto& [rate, wd] :
       {std::pair{*remedy.rate_hz, 100.0}, std::pair{200.0, *remedy.omega_d_hz}}) {
    const auto p = one_strut(rate, wd);
    CHECK_NOTHROW(scene::require_stable_loop(p));
    const RuntimeRun run = run_runtime_loop(p, 100000);
    INFO(rate << " Hz, omega_d " << wd << " Hz: largest " << run.largest << " N, first "
              << run.initial << " N, spectral radius " << radius(p));
    CHECK(run.steps == 100000);
    CHECK(run.largest <= 10 * run.initial);
    CHECK(radius(p) <= 1 + 1e-9);
  }
  // The suggestion is the lowest rate of the series: the one below it (if above 200 Hz) diverges.
  // (1 -> 0.5, 2 -> 1, 5 -> 2 times the decade).
  const double below =
      *remedy.rate_hz / (std::fmod(std::log10(*remedy.rate_hz), 1.0) > 0.5 ? 2.5 : 2.0);
  if (below > 200) {
    const auto p = one_strut(below, 100.0);
    const RuntimeRun run = run_runtime_loop(p, 1000000);
    INFO(below << " Hz: growth " << run.growth << ", spectral radius " << radius(p));
    CHECK(radius(p) > 1);
    CHECK(run.growth > 1);
    CHECK(run.largest > 1e3 * run.initial);
  }
  // 2 % above the suggested omega_d (3 significant digits, rounded down from the bisection's
  // bound) the loop at 200 Hz diverges, at the rate the model gives.
  {
    const auto p = one_strut(200, 1.02 * *remedy.omega_d_hz);
    const RuntimeRun run = run_runtime_loop(p, 1000000, 0, 1000);
    INFO("growth " << run.growth << ", spectral radius " << radius(p));
    CHECK(radius(p) > 1);
    CHECK(run.largest > 1e3 * run.initial);
    CHECK(std::abs(run.growth / radius(p) - 1) < 1e-3);
  }
}

TEST_CASE(
    "sampled loop: with the plant's mode above Nyquist the model still gives the runtime's "
    "growth and the omega_d bound",
    "[controller][sampled]") {
  // At 25 Hz the strut's mode (sqrt(k / m) / 2 pi = 36.5 Hz) lies at 2.9 times Nyquist: the
  // sampled plant aliases it, and only the sampled loop (not the continuous one) can say which
  // omega_d runs. The refusal's bound is checked in the runtime loop on both sides.
  const double rate = 25, mode_hz = std::sqrt(5263789.013914328 / 100.0) / (2 * 3.14159265358979);
  REQUIRE(mode_hz > 2.5 * rate / 2);
  const auto remedy = scene::stable_sampled_loop_remedy(one_strut(rate, 100.0));
  REQUIRE(remedy.omega_d_hz);
  INFO("omega_d bound at " << rate << " Hz: " << *remedy.omega_d_hz << " Hz");
  CHECK(*remedy.omega_d_hz < 100);
  const auto below = one_strut(rate, 0.98 * *remedy.omega_d_hz);
  CHECK_NOTHROW(scene::require_stable_loop(below));
  const RuntimeRun ok = run_runtime_loop(below, 100000);
  CHECK(ok.steps == 100000);
  CHECK(ok.largest <= 10 * ok.initial);
  const auto above = one_strut(rate, 1.02 * *remedy.omega_d_hz);
  CHECK_THROWS_AS(scene::require_stable_loop(above), common::InputError);
  const RuntimeRun run = run_runtime_loop(above, 1000000, 0, 1000);
  INFO("runtime growth " << run.growth << ", spectral radius " << radius(above));
  CHECK(radius(above) > 1);
  CHECK(run.largest > 1e3 * run.initial);
  CHECK(std::abs(run.growth / radius(above) - 1) < 1e-3);
}

TEST_CASE("sampled loop: the sensor path's delay is in the model and in the refusal",
          "[controller][sampled]") {
  // The suggested rate is stable without delay; a transport delay of a few samples makes it
  // unstable, and the runtime loop with the same delay grows at the model's spectral radius.
  const auto remedy = scene::stable_sampled_loop_remedy(one_strut());
  REQUIRE(remedy.rate_hz);
  int delay = 0;
  double rho = 0;
  for (int d = 1; d <= 32 && delay == 0; ++d)
    if ((rho = radius(one_strut(*remedy.rate_hz, 100.0, d))) > 1.01) delay = d;
  INFO("delay " << delay << " samples, spectral radius " << rho);
  REQUIRE(delay > 0);
  const auto p = one_strut(*remedy.rate_hz, 100.0, delay);
  CHECK(p.loop.stable());
  CHECK_THROWS_WITH(
      scene::require_stable_loop(p),
      Catch::Contains(std::to_string(delay) + (delay == 1 ? " sample" : " samples") + " of delay"));
  const RuntimeRun run = run_runtime_loop(p, 1000000, delay, 1000);
  INFO("runtime growth " << run.growth);
  CHECK(run.largest > 1e3 * run.initial);
  CHECK(std::abs(run.growth / rho - 1) < 1e-3);
  // One sample less is stable, and runs bounded.
  if (delay > 1) {
    const auto q = one_strut(*remedy.rate_hz, 100.0, delay - 1);
    if (radius(q) <= 1 + 1e-9) {
      const RuntimeRun ok = run_runtime_loop(q, 100000, delay - 1);
      CHECK(ok.largest <= 10 * ok.initial);
    }
  }
}

TEST_CASE("sampled loop: without hardware effects it is close_loop_sampled's loop",
          "[controller][sampled]") {
  // An independent formulation (plant/lti/feedback_interconnection): the metrology frame's plant
  // and controller discretised by zoh and closed with the held command. Same eigenvalues.
  const auto p = scene::build_scene_plant(scene::load_scene("tools/scenes/metrology_frame.toml"));
  const plant::lti::DiscretisationOptions o{plant::lti::DiscretisationMethod::kZeroOrderHold, 1e-4,
                                            0, false};
  const auto g22 = plant::lti::discretise(p.feedback_path, o);
  controller::design::SampledLoopHardware hw;
  hw.removed_feedthrough = g22.sys.D;
  const auto mine = controller::design::sampled_loop_stability(g22, p.gains, hw);
  const auto c = plant::lti::discretise(p.controller, o);
  const auto reference = plant::lti::close_loop_sampled(g22, c, {0, 0});
  // Every pole of the reference is one of the loop's (the loop's extra states, the command
  // remembered by the controller beside the one the plant holds, add poles at z = 0). Both sets
  // of eigenvalues after balancing: the loop has six-fold poles (one per strut) at z = 1 and at
  // the placed pair, which unbalanced eigenvalues put up to 6e-5 apart.
  const Eigen::VectorXd t = plant::lti::balancing_scaling(reference.sys.A);
  const Eigen::VectorXcd ref = Eigen::EigenSolver<Eigen::MatrixXd>(t.cwiseInverse().asDiagonal() *
                                                                   reference.sys.A * t.asDiagonal())
                                   .eigenvalues();
  REQUIRE(ref.size() == 24);
  REQUIRE(mine.poles.size() == 30);
  for (const auto& z : ref) {
    double nearest = 1e300;
    for (const auto& w : mine.poles) nearest = std::min(nearest, std::abs(z - w));
    INFO("pole " << z);
    CHECK(nearest <= 1e-6);
  }
  const double ref_radius = ref.cwiseAbs().maxCoeff();
  INFO("spectral radius " << mine.spectral_radius << " vs " << ref_radius);
  CHECK(std::abs(mine.spectral_radius - ref_radius) <= 1e-12);
  int at_zero = 0;
  for (const auto& w : mine.poles) at_zero += std::abs(w) <= 1e-6;
  CHECK(at_zero >= 6);
}

TEST_CASE("sampled loop: the metrology frame's scenes pass, their integrator poles are marginal",
          "[controller][sampled]") {
  // The default scene at 10 kHz: the pure integrator's six poles at z = 1 (marginal, as at s = 0
  // in the continuous loop), every other pole strictly inside.
  const auto p = scene::build_scene_plant(scene::load_scene("tools/scenes/metrology_frame.toml"));
  CHECK_NOTHROW(scene::require_stable_loop(p));
  const auto s = scene::sampled_loop(p);
  INFO("spectral radius " << s.stability.spectral_radius << ", inner "
                          << s.stability.largest_inner_radius << ", tolerance "
                          << s.stability.tolerance);
  CHECK(s.stability.stable());
  CHECK(s.stability.marginal == 6);
  CHECK(std::abs(s.stability.spectral_radius - 1) <= s.stability.tolerance);
  CHECK(s.stability.largest_inner_radius < 1 - 1e-4);
  // Every effect (2 samples of delay, a lagging actuator, sensor gain error, a leak): stable, no
  // pole on the circle (the leak moves the integrator's inside).
  const auto all =
      scene::build_scene_plant(scene::load_scene("tools/scenes/metrology_frame_all_effects.toml"));
  CHECK_NOTHROW(scene::require_stable_loop(all));
  const auto a = scene::sampled_loop(all);
  CHECK(a.hardware.feedthrough_delay == 2);
  CHECK(a.hardware.actuator_lag_s == 0.0002);
  CHECK(a.stability.stable());
  CHECK(a.stability.marginal == 0);
  CHECK(a.stability.spectral_radius < 1);
}
