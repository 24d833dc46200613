// Consistency of the in-process loop (tools/sim/closed_loop_run.hpp) with the offline analysis:
// for a white floor, the simulated closed-loop frame-acceleration spectrum (Welch) equals
// sum_j |T_ij(e^{jwT})|^2 times the input density, T the sampled closed loop of
// plant/lti/feedback_interconnection.hpp, within 1 dB over 1-200 Hz.
#include <catch2/catch.hpp>

#include <cmath>

#include "controller/runtime/pi_controller_sizes.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/welch.hpp"
#include "plant/runtime/runtime_sizes.hpp"
#include "tools/scene/scene_plant.hpp"
#include "tools/sim/closed_loop_run.hpp"
#include "tools/sim/scene_hardware.hpp"

using namespace flexloop;

TEST_CASE(
    "sim: closed-loop frame spectrum for a white floor matches |T(e^jwT)|^2 within 1 dB "
    "over 1-200 Hz",
    "[sim][spectrum]") {
  auto sc = scene::load_scene("tools/scenes/metrology_frame.toml");
  // 1 kHz keeps 600 s of log small; 1-200 Hz stays well below Nyquist. A leak keeps the
  // integrator poles off z = 1 (the test compares a stationary spectrum).
  sc.discretisation.rate_hz = 1000;
  sc.controller.leak_hz = 0.2;
  const auto p = scene::build_scene_plant(sc);
  const auto sampled = scene::sample_scene(p);
  const auto& d = sampled.plant.sys;
  REQUIRE(d.nx() == 12);
  REQUIRE(d.nu() == 12);

  sim::RunSettings s;
  s.dt = sampled.plant.dt;
  s.steps = 600'000;  // 600 s
  s.log_every = 1;
  const double floor_rms = 1e-3;
  using Plant = plant::runtime::DensePlant<double, 12, 12, 12>;
  using Floor = plant::runtime::effects::WhiteFloor<double, 6>;
  const auto r = sim::run_closed_loop(
      plant::runtime::SimulatedHardware<Plant, 6, 6, Floor>(
          Plant::from_matrices(d.A, d.B, d.C, d.D), Floor::from_parameters(floor_rms, 11)),
      controller::runtime::PiController<double, 6>::from_parameters(
          sim::pi_parameters_with_hardware(p, s.dt)),
      s, {});

  const double fs = 1.0 / s.dt;
  const double input_psd = 2 * floor_rms * floor_rms / fs;  // one-sided, white
  const Eigen::Index L = 2048;                              // 0.49 Hz bins, 585 segments
  double worst_db = 0, worst_f = 0;
  for (int i = 0; i < 6; ++i) {
    const auto est = plant::lti::welch_psd(r.log.col(1 + 6 + i), fs, {L, 0.5});
    // Compare band averages (bins within +-5 % of each check frequency) of estimate and theory;
    // the estimate's relative standard deviation per bin is about 1/sqrt(segments) = 4 %.
    for (double fc = 1.0; fc <= 200.0; fc *= 1.12) {
      std::vector<double> f;
      double sum_est = 0;
      for (Eigen::Index k = 1; k < est.psd.size(); ++k)
        if (std::abs(est.frequency_hz(k) - fc) <= std::max(0.05 * fc, 0.5 * fs / L))
          f.push_back(est.frequency_hz(k)), sum_est += est.psd(k);
      const auto T = plant::lti::frequency_response(sampled.closed_loop, f);
      double sum_theory = 0;
      for (const auto& t : T) sum_theory += t.row(i).squaredNorm() * input_psd;
      const double err_db = 10 * std::log10(sum_est / sum_theory);
      if (std::abs(err_db) > std::abs(worst_db)) worst_db = err_db, worst_f = fc;
    }
  }
  INFO("worst deviation " << worst_db << " dB at " << worst_f << " Hz");
  WARN("Welch vs |T|^2: worst deviation " << worst_db << " dB at " << worst_f << " Hz");
  CHECK(std::abs(worst_db) <= 1.0);
}
