// SPDX-License-Identifier: BSD-3-Clause
// `flexloop sim SCENE|LOOP.json [--duration S] [--controller on|off] [--form dense|modal]
//  [--start stationary|rest] [--log OUT.csv] [--log-every N] [--json OUT.json] [--plots DIR]`:
// the discrete plant, hardware and controller in one process, faster than real time
// (online/sim/closed_loop_run.hpp has the loop), once with the controller off and once on, driven
// by the same seeded floor; prints the RMS of every performance output for both and writes the
// log of the requested run. A scene is first built into its artefact
// (offline/scene/loop_input.hpp), as `flexloop build` does. The runs and their judgement are
// online/sim/sim_command.hpp's, which the Python module's flexloop.sim calls too; this file prints
// and writes.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>

#include <nlohmann/json.hpp>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/report/csv_writer.hpp"
#include "offline/report/plot.hpp"
#include "offline/report/table_file.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/closed_loop_run.hpp"
#include "online/sim/scene_runs.hpp"
#include "online/sim/sim_command.hpp"
#include "plant/lti/welch.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

struct SimArgs {
  std::string scene, log, plots, json, controller, form, path = "auto", start = "stationary";
  double duration_s = 0;
  long log_every = 1;
};

using sim::BothRuns;

// "1h02m", "3m05s", "12s": a time left.
std::string duration_text(double s) {
  char t[48];
  if (s >= 3600)
    std::snprintf(t, sizeof t, "%.0fh%02.0fm", std::floor(s / 3600),
                  std::floor(std::fmod(s, 3600) / 60));
  else if (s >= 60)
    std::snprintf(t, sizeof t, "%.0fm%02.0fs", std::floor(s / 60), std::floor(std::fmod(s, 60)));
  else
    std::snprintf(t, sizeof t, "%.1fs", s);
  return t;
}

// Progress on long runs only, with the time left at the rate so far: an updating line on a
// terminal (at most twice a second), otherwise a line per quarter and at least one a minute.
sim::ProgressFactory progress_lines(long steps) {
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  return [tty, steps](const char* what) -> std::function<void(long, long)> {
    if (steps < 1'000'000) return {};
    using Clock = std::chrono::steady_clock;
    return [what, tty, start = Clock::now(), last = Clock::time_point{}, quarter = 0L](
               long done, long total) mutable {
      const auto now = Clock::now();
      const double elapsed = std::chrono::duration<double>(now - start).count();
      const double since = std::chrono::duration<double>(now - last).count();
      const long q = 4 * done / total;
      const bool end = done == total;
      if (!end && (tty ? since < 0.5 : q == quarter && since < 60)) return;
      last = now;
      quarter = q;
      const double pct = 100.0 * static_cast<double>(done) / static_cast<double>(total);
      const std::string left = end ? "done in " + duration_text(elapsed)
                                   : duration_text(elapsed * static_cast<double>(total - done) /
                                                   static_cast<double>(done)) +
                                         " left";
      std::fprintf(
          stderr,
          tty ? "\r  %s: %5.1f%% of %ld steps, %s   %s" : "  %s: %5.1f%% of %ld steps, %s%s", what,
          pct, total, left.c_str(), tty && !end ? "" : "\n");
    };
  };
}

// The log's data: every log_every-th of `steps` rows of `columns` doubles.
double log_bytes(long steps, long log_every, Eigen::Index columns) {
  return std::ceil(static_cast<double>(steps) / static_cast<double>(log_every)) *
         static_cast<double>(columns) * sizeof(double);
}

// A log that does not fit: refused before the run, with the --log-every that would.
void require_log_fits(long steps, long log_every, Eigen::Index columns, const std::string& path) {
  const double bytes = log_bytes(steps, log_every, columns);
  const double memory = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                        static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  if (bytes <= memory / 2) return;
  throw common::InputError(
      path,
      "the log would take " + report::format_number(std::ceil(bytes / 1e9)) +
          " GB, more than half of this machine's memory; log every " +
          report::format_number(std::ceil(bytes / (memory / 2)) * static_cast<double>(log_every)) +
          "-th sample (--log-every) or run shorter");
}

// A .mat log above MAT 5's 2 GB per variable (MATLAB reads no larger one from a MAT 5 file):
// refused before the run, with the --log-every that fits; a CSV has no such limit.
void require_mat_fits(long steps, long log_every, Eigen::Index columns, const std::string& path) {
  const double bytes = log_bytes(steps, log_every, columns);
  constexpr double kLimit = 2147483648.0 - 4096;  // 2^31, less the header and tags
  if (std::filesystem::path(path).extension() != ".mat" || bytes <= kLimit) return;
  throw common::InputError(
      path, "the log would take " + report::format_number(std::ceil(bytes / 1e9)) +
                " GB, more than a MAT 5 file holds in one variable (2 GB); log every " +
                report::format_number(std::ceil(bytes / kLimit) * static_cast<double>(log_every)) +
                "-th sample (--log-every), run shorter, or write .csv");
}

std::string describe_effects(const artefact::EffectsSettings& e) {
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

void plot_runs(const artefact::LoopArtefact& a, const BothRuns& r, long log_every,
               const std::string& dir) {
  std::filesystem::create_directories(dir);
  const Eigen::Index nw = a.disturbances(), nz = a.performance();
  const auto& disturbance = a.channels.disturbances[0];
  const auto& performance = a.channels.performance;
  const double rate_hz = a.rate_hz;
  // Time series of the first frame channel and the floor: the last 2000 logged samples.
  const Eigen::Index rows = r.on.log.rows(), keep = std::min<Eigen::Index>(rows, 2000);
  const Eigen::Index first = rows - keep;
  auto column = [&](const sim::RunLog& log, Eigen::Index c) {
    std::vector<double> v(static_cast<std::size_t>(keep));
    for (Eigen::Index i = 0; i < keep; ++i)
      v[static_cast<std::size_t>(i)] = log.matrix()(first + i, c);
    return v;
  };
  const auto t = column(r.on.log, 0);
  // One panel each (own y range): the disturbance, the output with the controller off, and on;
  // the "on" trace is tens of dB below the "off" one and would be a flat line beside it.
  const std::string unit = "[" + performance[0].unit + "]";
  std::vector<report::Panel> panels{
      {"disturbance [" + disturbance.unit + "]",
       {{disturbance.name, t, column(r.on.log, 1), "lines lw 1 lc 3"}}},
      {"controller off " + unit,
       {{performance[0].name + ", controller off", t, column(r.off.log, 1 + nw),
         "lines lw 1 lc 1"}}}};
  if (r.controlled)
    panels.push_back({"controller on " + unit,
                      {{performance[0].name + ", controller on", t, column(r.on.log, 1 + nw),
                        "lines lw 1 lc 2"}}});
  char window[160] = "";
  if (keep > 0)
    std::snprintf(window, sizeof window, ", t = %.4g ... %.4g s (the last %lld logged samples)",
                  t.front(), t.back(), static_cast<long long>(keep));
  report::plot_stacked({a.name + ": disturbance and performance output" + window, "time [s]", "",
                        false, false, 1200, 300 + 250 * static_cast<int>(panels.size())},
                       panels, dir + "/time_series.png");
  // Welch spectra of every frame channel, off (solid) and on (dashed).
  const double fs = rate_hz / static_cast<double>(log_every);  // the log's sample rate
  const Eigen::Index L = std::min<Eigen::Index>(r.on.log.rows() / 8, 8192);
  std::vector<report::Series> sp;
  for (Eigen::Index i = 0; i < nz && L >= 16; ++i)
    for (const auto* run : {&r.off, &r.on}) {
      if (run == &r.on && !r.controlled) continue;
      const auto s = plant::lti::welch_psd(run->log.matrix().col(1 + nw + i), fs, {L, 0.5});
      std::vector<double> f, v;
      for (Eigen::Index k = 1; k < s.psd.size(); ++k)
        f.push_back(s.frequency_hz(k)), v.push_back(std::sqrt(s.psd(k)));
      sp.push_back(
          {performance[static_cast<std::size_t>(i)].name + (run == &r.off ? " off" : " on"), f, v,
           std::string(run == &r.off ? "lines lw 1 dt 1" : "lines lw 2 dt 2") + " lc " +
               std::to_string(i + 1)});
    }
  report::plot_lines(
      {a.name + ": performance spectra (solid off, dashed on)", "frequency [Hz]",
       "amplitude spectral density [" + performance[0].unit + "/sqrt(Hz)]", true, true, 1200, 700},
      sp, dir + "/spectra.png");
}

// What the controller said of its run (controller/runtime/loop_controller.hpp: a controller FMU's
// log and warnings) goes to stderr. A run it could not complete (fmi2Discard, fmi2Pending: the
// loop held the safe command from there) fails in sim::require_completed; a refusal (fmi2Error,
// fmi2Fatal) is an input error that sim::run_artefact threw already.
void report_controller(const artefact::LoopArtefact& a, const sim::RunResult& on) {
  const controller::runtime::ControllerReport& c = on.controller;
  for (const std::string& m : c.messages) std::fprintf(stderr, "%s\n", m.c_str());
  if (c.messages_lost > 0)
    std::fprintf(stderr, "(%ld more messages of the controller did not fit its log ring)\n",
                 c.messages_lost);
  if (c.warnings > 0)
    std::fprintf(stderr, "warning: %s: fmi2Warning returned %ld times; the first: %s\n",
                 a.fmu.file.c_str(), c.warnings, c.first_warning.c_str());
}

void print_loop(const artefact::LoopArtefact& a, long steps) {
  const std::string floor =
      a.floor.spectrum == artefact::FloorSpectrum::kWhite
          ? "white " + report::format_number(a.floor.rms_mps2) + " m/s^2 RMS per channel"
          : artefact::to_string(a.floor.spectrum) + " (IEST-RP-CC012, flat velocity 1-80 Hz)";
  std::printf("scene %s: %s plant, %ld states, %.0f Hz (%s), %.3g s = %ld steps\n", a.name.c_str(),
              artefact::to_string(a.plant.form).c_str(), static_cast<long>(a.plant.states.size()),
              a.rate_hz, artefact::to_string(a.method).c_str(), a.duration_s, steps);
  std::printf(
      "channels: %ld disturbances, %ld actuators, %ld performance outputs, %ld sensors; "
      "controller: %s\n",
      static_cast<long>(a.disturbances()), static_cast<long>(a.actuators()),
      static_cast<long>(a.performance()), static_cast<long>(a.sensors()),
      artefact::to_string(a.controller).c_str());
  std::printf("floor: %s, seed %llu\neffects: %s\n", floor.c_str(),
              static_cast<unsigned long long>(a.floor.seed), describe_effects(a.effects).c_str());
}

void print_rms(const artefact::LoopArtefact& a, const BothRuns& r) {
  std::printf("RMS of the performance outputs   controller off   controller on   change\n");
  for (const sim::RmsRow& row : sim::rms_table(a, r)) {
    const std::string label = row.channel + " [" + row.unit + "]";
    if (r.controlled)
      std::printf("  %-28s %14.4e %15.4e %+7.1f dB\n", label.c_str(), row.off, row.on,
                  row.change_db);
    else
      std::printf("  %-28s %14.4e %15s\n", label.c_str(), row.off, "-");
  }
  if (r.controlled)
    std::printf("RMS actuator command with the controller on: %.4g %s (largest channel)\n",
                r.on.rms_command.maxCoeff(), a.channels.actuators[0].unit.c_str());
}

// --json: the run's figures to the bit (JSON numbers read back to the same doubles; a figure
// that does not exist, the controller-on RMS of a loop without one, is null).
void write_sim_json(const artefact::LoopArtefact& a, const BothRuns& r, bool on,
                    const std::string& path) {
  const auto number = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  nlohmann::json rms = nlohmann::json::array();
  for (const sim::RmsRow& row : sim::rms_table(a, r))
    rms.push_back({{"channel", row.channel},
                   {"unit", row.unit},
                   {"off", number(row.off)},
                   {"on", number(row.on)},
                   {"change_db", number(row.change_db)}});
  nlohmann::json command = nlohmann::json::array();
  if (r.controlled)
    for (Eigen::Index i = 0; i < r.on.rms_command.size(); ++i)
      command.push_back({{"channel", a.channels.actuators[static_cast<std::size_t>(i)].name},
                         {"on", number(r.on.rms_command(i))}});
  const nlohmann::json j = {{"scene", a.name},
                            {"rate_hz", a.rate_hz},
                            {"duration_s", a.duration_s},
                            {"steps", sim::sim_settings(a, 1).steps},
                            {"floor_seed", a.floor.seed},
                            {"controlled", r.controlled},
                            {"logged", on ? "on" : "off"},
                            {"start_off", r.start_off},
                            {"start_on", r.start_on},
                            {"rms", rms},
                            {"rms_command", command}};
  common::write_text_atomically(path, j.dump(1) + "\n");
}

void run(const SimArgs& args) {
  const artefact::LoopArtefact a = scene::load_loop(
      args.scene, {.rate_hz = 0,
                   .form = args.form.empty() ? std::nullopt
                                             : std::optional(artefact::parse_plant_form(args.form)),
                   .duration_s = args.duration_s});
  const bool plots = !args.plots.empty(), log = !args.log.empty();
  sim::SimRequest request;
  request.controller_on = args.controller.empty() || args.controller == "on";
  request.start = args.start == "rest" ? sim::StartKind::kRest : sim::StartKind::kStationary;
  request.general = args.path == "general";
  request.log_every = args.log_every;
  request.log = log;
  request.log_both = plots;
  const bool on = sim::logs_controller_on(a, request);
  const sim::RunSettings s = sim::sim_settings(a, args.log_every);
  if (log && !report::is_table_file(args.log))
    throw common::InputError(args.log, "--log writes .csv or .mat");
  if (log) common::require_writable(args.log);  // before the run, not after it
  if (!args.json.empty()) common::require_writable(args.json);
  if (log || plots) {  // plots log both runs
    const auto columns = static_cast<Eigen::Index>(sim::log_header(a).size());
    require_log_fits(s.steps, s.log_every, plots ? 2 * columns : columns,
                     log ? args.log : args.plots);
    if (log) require_mat_fits(s.steps, s.log_every, columns, args.log);
  }
  if (plots) common::require_writable(std::filesystem::path(args.plots) / "time_series.png");
  print_loop(a, s.steps);
  if (log)
    if (const auto dir = std::filesystem::path(args.log).parent_path(); !dir.empty())
      std::filesystem::create_directories(dir);
  // The logged run goes first, and its file is written while the other run goes on: on two
  // cores the writing (formatting, the kernel's copy, fsync) hides behind that run. Declared in
  // this order so that the writer is joined before the log it reads is freed and before an
  // unfinished file is removed.
  sim::RunLog written;
  struct Staged {
    const std::string* path = nullptr;
    bool committed = false;
    ~Staged() {
      if (path && !committed) report::discard_table(*path);
    }
  } staged;
  std::exception_ptr write_error;
  std::jthread writer;
  const auto write_first = [&](sim::RunResult& first) {
    if (!log || first.divergence.happened()) return;
    written = std::move(first.log);
    staged.path = &args.log;
    writer = std::jthread([&] {
      try {
        report::stage_table(args.log, sim::log_header(a), written.matrix());
      } catch (...) {
        write_error = std::current_exception();
      }
    });
  };
  request.progress = progress_lines(s.steps);
  request.after_first_run = write_first;
  BothRuns r = sim::run_sim(a, request);
  std::printf("start: controller off %s%s%s\n", r.start_off.c_str(),
              r.controlled ? "; controller on " : "", r.controlled ? r.start_on.c_str() : "");
  if (r.controlled) report_controller(a, r.on);
  if (writer.joinable()) {
    writer.join();
    (on ? r.on : r.off).log = std::move(written);  // back for the plots
  }
  sim::require_completed(a, r);
  print_rms(a, r);
  for (const auto* run : {&r.off, &r.on}) {
    if (run == &r.on && !r.controlled) continue;
    std::printf("%s: loop %.3f s wall for %.3g s simulated: %.0fx real time\n",
                run == &r.off ? "controller off" : "controller on ", run->loop_seconds,
                a.duration_s, a.duration_s / run->loop_seconds);
  }
  if (log) {
    if (write_error) std::rethrow_exception(write_error);
    report::commit_table(args.log);
    staged.committed = true;
    std::printf("wrote %s (controller %s, every %ld-th sample)\n", args.log.c_str(),
                on ? "on" : "off", args.log_every);
  }
  if (!args.json.empty()) {
    write_sim_json(a, r, on, args.json);
    std::printf("wrote %s\n", args.json.c_str());
  }
  if (plots) {
    plot_runs(a, r, args.log_every, args.plots);
    std::printf("wrote %s/{time_series.png, spectra.png}\n", args.plots.c_str());
  }
}

}  // namespace

void register_sim(CLI::App& app) {
  auto args = std::make_shared<SimArgs>();
  auto* cmd = app.add_subcommand(
      "sim",
      "Run a loop (a scene, or an artefact of flexloop build) in one process, faster than real "
      "time");
  cmd->add_option("loop", args->scene, "Scene file (TOML) or loop artefact (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--duration", args->duration_s, "Simulated time [s] (default: the scene's)")
      ->check(finite_positive());
  cmd->add_option("--controller", args->controller,
                  "Log the run with the controller on or off (default: the scene's); the "
                  "summary shows both")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--form", args->form,
                  "Plant form of a scene: dense or modal (real block-diagonal); an artefact "
                  "has its own")
      ->check(CLI::IsMember({"dense", "modal"}));
  cmd->add_option("--runtime-path", args->path,
                  "auto: a compiled fast path where the plant's sizes have one, else the general "
                  "path sized at start-up; general: the general path always (for comparisons)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "general"}));
  cmd->add_option("--start", args->start,
                  "stationary: each run starts in a draw from its loop's stationary distribution "
                  "(the same seeds, the same draw), where the loop has one; rest: plant, "
                  "hardware and controller at rest, the floor stationary")
      ->capture_default_str()
      ->check(CLI::IsMember({"stationary", "rest"}));
  cmd->add_option("--log", args->log,
                  "Log: t_s, disturbances, performance outputs (true and as sensed), sensors, "
                  "commands (SI units), one row per logged sample; .csv (text) or .mat (MATLAB "
                  "MAT 5, binary: `data` and `columns`, for long runs)");
  cmd->add_option("--log-every", args->log_every, "Log every N-th sample")
      ->capture_default_str()
      ->check(finite_positive());
  cmd->add_option("--json", args->json,
                  "Write the run's figures as JSON: per performance output the RMS with the "
                  "controller off and on and the change in dB, each command's RMS (controller "
                  "on), the seed and the start (numbers that read back to the same doubles)");
  cmd->add_option("--plots", args->plots,
                  "Directory for time_series.png and spectra.png (controller off and on)");
  cmd->footer(
      "Example:\n  flexloop sim tools/scenes/metrology_frame.toml --duration 10 --log "
      "out/sim/metrology.csv --plots out/sim\n"
      "Exit: 0 done; 2 bad input or a loop the checks refuse (file:line says why); 1 a run that "
      "diverged (|[z; u]| > 1e12 or not finite: when and on which channel), nothing written.");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
