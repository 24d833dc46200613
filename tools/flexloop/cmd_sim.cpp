// `flexloop sim SCENE [--duration S] [--controller on|off] [--form dense|modal] --log OUT.csv
//  [--log-every N] [--plots DIR]`: the scene's discrete plant and PI controller in one process,
// faster than real time (tools/sim/closed_loop_run.hpp has the loop), once with the controller
// off and once on, driven by the same seeded floor; prints the RMS frame acceleration per
// channel for both and writes the log of the requested run.
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "plant/lti/welch.hpp"
#include "plant/model/input_error.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/report/csv_writer.hpp"
#include "tools/report/plot.hpp"
#include "tools/scene/scene_plant.hpp"
#include "tools/sim/closed_loop_run.hpp"
#include "tools/sim/scene_runs.hpp"

namespace flexloop::cli {

namespace {

struct SimArgs {
  std::string scene, log, plots, controller, form = "dense";
  double duration_s = 0;
  long log_every = 1;
};

using sim::BothRuns;

// Progress on long runs only: an updating line on a terminal, a line per quarter otherwise.
sim::ProgressFactory progress_lines(long steps) {
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  return [tty, steps](const char* what) -> std::function<void(long, long)> {
    if (steps < 1'000'000) return {};
    return [what, tty](long done, long total) {
      const long pct = 100 * done / total;
      if (tty)
        std::fprintf(stderr, "\r  %s: %3ld%% of %ld steps%s", what, pct, total,
                     done == total ? "\n" : "");
      else if (pct % 25 == 0)
        std::fprintf(stderr, "  %s: %3ld%% of %ld steps\n", what, pct, total);
    };
  };
}

std::string describe_effects(const scene::EffectsSettings& e) {
  std::string d;
  auto add = [&d](const std::string& s) { d += (d.empty() ? "" : "; ") + s; };
  auto num = [](double v) { return report::format_number(v); };
  if (e.actuator.present)
    add("piezo actuator (gain " + num(e.actuator.gain) + ", +-" + num(e.actuator.force_limit_n) +
        " N" + (e.actuator.lag_s > 0 ? ", lag " + num(e.actuator.lag_s) + " s" : "") + ")");
  for (auto [name, sensor, unit] : {std::tuple{"force sensors", &e.force_sensor, "N"},
                                    std::tuple{"accelerometers", &e.accelerometer, "m/s^2"}})
    if (sensor->present)
      add(std::string(name) + " (noise " + num(sensor->noise_rms) + " " + unit + " RMS, " +
          std::to_string(sensor->adc_bits) + " bit over " + num(sensor->adc_range) + " " + unit +
          (sensor->gain_error != 0 ? ", gain error " + num(sensor->gain_error) : "") +
          (sensor->delay_samples > 0 ? ", delay " + std::to_string(sensor->delay_samples) : "") +
          ")");
  if (e.transport_delay_samples > 0)
    add("transport delay " + std::to_string(e.transport_delay_samples) + " samples");
  return d.empty() ? "none (bare plant)" : d;
}

std::vector<std::string> log_header(const scene::ScenePlant& p) {
  std::vector<std::string> h{"t_s"};
  for (const auto& n : p.scene.disturbances) h.push_back("floor " + n);
  for (const auto& n : p.scene.performance) h.push_back("frame " + n);
  for (const auto& n : p.scene.performance) h.push_back("accelerometer " + n);
  for (const auto& n : p.scene.sensors) h.push_back("force sensor " + n);
  for (const auto& n : p.scene.actuators) h.push_back("command " + n);
  return h;
}

void plot_runs(const scene::ScenePlant& p, const BothRuns& r, double rate_hz, long log_every,
               const std::string& dir) {
  std::filesystem::create_directories(dir);
  const Eigen::Index nw = p.partition.disturbances, nz = p.partition.performance;
  // Time series of the first frame channel and the floor: the last 2000 logged samples.
  const Eigen::Index rows = r.on.log.rows(), keep = std::min<Eigen::Index>(rows, 2000);
  const Eigen::Index first = rows - keep;
  auto column = [&](const Eigen::MatrixXd& log, Eigen::Index c) {
    std::vector<double> v(static_cast<std::size_t>(keep));
    for (Eigen::Index i = 0; i < keep; ++i) v[static_cast<std::size_t>(i)] = log(first + i, c);
    return v;
  };
  const auto t = column(r.on.log, 0);
  std::vector<report::Series> ts{
      {"floor " + p.scene.disturbances[0], t, column(r.on.log, 1), "lines lw 1 lc 3"},
      {"frame " + p.scene.performance[0] + ", controller off", t, column(r.off.log, 1 + nw),
       "lines lw 1 lc 1"},
      {"frame " + p.scene.performance[0] + ", controller on", t, column(r.on.log, 1 + nw),
       "lines lw 2 lc 2"}};
  report::plot_lines({p.scene.name + ": floor and frame acceleration", "time [s]",
                      "acceleration [m/s^2]", false, false, 1200, 500},
                     ts, dir + "/time_series.png");
  // Welch spectra of every frame channel, off (solid) and on (dashed).
  const double fs = rate_hz / static_cast<double>(log_every);  // the log's sample rate
  const Eigen::Index L = std::min<Eigen::Index>(r.on.log.rows() / 8, 8192);
  std::vector<report::Series> sp;
  for (Eigen::Index i = 0; i < nz && L >= 16; ++i)
    for (const auto* run : {&r.off, &r.on}) {
      const auto s = plant::lti::welch_psd(run->log.col(1 + nw + i), fs, {L, 0.5});
      std::vector<double> f, v;
      for (Eigen::Index k = 1; k < s.psd.size(); ++k)
        f.push_back(s.frequency_hz(k)), v.push_back(std::sqrt(s.psd(k)));
      sp.push_back(
          {p.scene.performance[static_cast<std::size_t>(i)] + (run == &r.off ? " off" : " on"), f,
           v,
           std::string(run == &r.off ? "lines lw 1 dt 1" : "lines lw 2 dt 2") + " lc " +
               std::to_string(i + 1)});
    }
  report::plot_lines(
      {p.scene.name + ": frame acceleration spectra (solid off, dashed on)", "frequency [Hz]",
       "amplitude spectral density [m/s^2/sqrt(Hz)]", true, true, 1200, 700},
      sp, dir + "/spectra.png");
}

void run(const SimArgs& a) {
  scene::Scene sc = scene::load_scene(a.scene);
  if (a.duration_s > 0) sc.run.duration_s = a.duration_s;
  const bool on = a.controller.empty() ? sc.controller.enabled : a.controller == "on";
  const auto p = scene::build_scene_plant(sc);
  scene::require_stable_loop(p);  // both runs are simulated, the controlled one too
  const auto sampled = scene::sample_scene(p);
  sim::RunSettings s;
  s.dt = sampled.plant.dt;
  s.steps = std::lround(sc.run.duration_s / s.dt);
  s.log_every = a.log_every;
  const bool plots = !a.plots.empty(), log = !a.log.empty();
  const std::string floor =
      sc.floor.spectrum == "white"
          ? "white " + report::format_number(sc.floor.rms_mps2) + " m/s^2 RMS per channel"
          : sc.floor.spectrum + " (IEST-RP-CC012, flat velocity 1-80 Hz)";
  std::printf("scene %s: %s plant, %ld states, %.0f Hz (%s), %.3g s = %ld steps\n", sc.name.c_str(),
              a.form.c_str(), static_cast<long>(sampled.plant.sys.nx()), sc.discretisation.rate_hz,
              plant::lti::to_string(sc.discretisation.method).c_str(), sc.run.duration_s, s.steps);
  std::printf("floor: %s, seed %llu\neffects: %s\n", floor.c_str(),
              static_cast<unsigned long long>(sc.floor.seed), describe_effects(sc.effects).c_str());
  const BothRuns r = sim::run_scene(
      p, sampled, s,
      {a.form, plots || (log && !on), plots || (log && on), progress_lines(s.steps)});

  std::printf("RMS frame acceleration [m/s^2]   controller off   controller on   change\n");
  for (Eigen::Index i = 0; i < r.on.rms_performance.size(); ++i)
    std::printf("  %-28s %14.4e %15.4e %+7.1f dB\n",
                p.scene.performance[static_cast<std::size_t>(i)].c_str(), r.off.rms_performance(i),
                r.on.rms_performance(i),
                20 * std::log10(r.on.rms_performance(i) / r.off.rms_performance(i)));
  std::printf("RMS actuator force with the controller on: %.4g N (largest channel)\n",
              r.on.rms_command.maxCoeff());
  for (const auto* run : {&r.off, &r.on})
    std::printf("%s: loop %.3f s wall for %.3g s simulated: %.0fx real time\n",
                run == &r.off ? "controller off" : "controller on ", run->loop_seconds,
                sc.run.duration_s, sc.run.duration_s / run->loop_seconds);
  if (log) {
    if (const auto dir = std::filesystem::path(a.log).parent_path(); !dir.empty())
      std::filesystem::create_directories(dir);
    report::write_csv(a.log, log_header(p), on ? r.on.log : r.off.log);
    std::printf("wrote %s (controller %s, every %ld-th sample)\n", a.log.c_str(), on ? "on" : "off",
                a.log_every);
  }
  if (plots) {
    plot_runs(p, r, sc.discretisation.rate_hz, a.log_every, a.plots);
    std::printf("wrote %s/{time_series.png, spectra.png}\n", a.plots.c_str());
  }
}

}  // namespace

void register_sim(CLI::App& app) {
  auto args = std::make_shared<SimArgs>();
  auto* cmd = app.add_subcommand(
      "sim",
      "Run a scene's discrete plant and PI controller in one process, faster than real time");
  cmd->add_option("scene", args->scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--duration", args->duration_s, "Simulated time [s] (default: the scene's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--controller", args->controller,
                  "Log the run with the controller on or off (default: the scene's); the "
                  "summary shows both")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--form", args->form, "Plant form: dense or modal (real block-diagonal)")
      ->capture_default_str()
      ->check(CLI::IsMember({"dense", "modal"}));
  cmd->add_option("--log", args->log,
                  "CSV log: t_s, floor accelerations, frame accelerations, sensor forces, "
                  "commands (SI units), one row per logged sample");
  cmd->add_option("--log-every", args->log_every, "Log every N-th sample")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--plots", args->plots,
                  "Directory for time_series.png and spectra.png (controller off and on)");
  cmd->footer(
      "Example:\n  flexloop sim tools/scenes/metrology_frame.toml --duration 10 --log "
      "out/sim/metrology.csv --plots out/sim");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
