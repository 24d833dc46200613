// SPDX-License-Identifier: BSD-3-Clause
// The Python module `flexloop` (issue 55, 3; doc/python.md): the command line's computations as
// functions, numpy arrays in and out, the same code and so the same bits as the CLI. An input the
// CLI refuses raises flexloop.InputError (a ValueError) with the CLI's message (file:line).
// linearise, build, load, analyse, sim (the runs of online/sim/sim_command.hpp) and campaign
// (make_plan, PlanSamples::line on threads, campaign_summary: offline/campaign).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "offline/campaign/campaign_plan.hpp"
#include "offline/campaign/campaign_report.hpp"
#include "offline/campaign/plan_samples.hpp"
#include "offline/pipeline/analyse_scene.hpp"
#include "offline/pipeline/linearised_model.hpp"
#include "offline/scene/loop_input.hpp"
#include "online/sim/sim_command.hpp"
#include "tools/flexloop/blas_threads.hpp"

namespace py = pybind11;

namespace {

using flexloop::pipeline::LinearisedModel;

// `flexloop linearise`'s state space and natural frequencies.
struct Linearised {
  Eigen::MatrixXd A, B, C, D;
  std::vector<std::string> states, inputs, outputs;
  Eigen::VectorXd natural_frequencies_hz;
};

Linearised linearise(const std::string& model, std::optional<std::vector<std::string>> inputs,
                     std::optional<std::vector<std::string>> outputs) {
  const LinearisedModel r =
      flexloop::pipeline::linearise_model_file(model, inputs.value_or(std::vector<std::string>{}),
                                               outputs.value_or(std::vector<std::string>{}));
  return {r.ss.A,      r.ss.B,      r.ss.C,       r.ss.D,
          r.ss.states, r.ss.inputs, r.ss.outputs, r.natural_frequencies_hz};
}

std::vector<std::string> names(const std::vector<flexloop::artefact::Channel>& channels) {
  std::vector<std::string> out;
  for (const auto& c : channels) out.push_back(c.name);
  return out;
}

// `flexloop build`: the scene's loop artefact, or an artefact file read back (rate_hz and form
// are a scene's: an artefact's are fixed).
flexloop::artefact::LoopArtefact build(const std::string& scene, std::optional<double> rate_hz,
                                       const std::string& form) {
  return flexloop::scene::load_loop(scene, {.rate_hz = rate_hz.value_or(0),
                                            .form = flexloop::artefact::parse_plant_form(form),
                                            .duration_s = 0});
}

// While alive, the process's standard output goes to /dev/null (analyse prints its report
// there); restored on every way out, an exception's included.
class SilencedStdout {
 public:
  SilencedStdout() {
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ >= 0 && null >= 0) ::dup2(null, STDOUT_FILENO);
    if (null >= 0) ::close(null);
  }
  ~SilencedStdout() {
    std::fflush(stdout);
    if (saved_ >= 0) ::dup2(saved_, STDOUT_FILENO), ::close(saved_);
  }
  SilencedStdout(const SilencedStdout&) = delete;
  SilencedStdout& operator=(const SilencedStdout&) = delete;

 private:
  int saved_ = -1;
};

// A folder removed when it goes out of scope.
struct ScratchFolder {
  std::filesystem::path path;
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

// `flexloop analyse SCENE`'s analysis.json as a dict: analyse writes into a temporary folder
// of this process (its report on standard output silenced), which is removed.
py::object analyse(const std::string& scene, double f_min_hz, double f_max_hz, int points) {
  const ScratchFolder dir{std::filesystem::temp_directory_path() /
                          ("flexloop_python_analyse_" + std::to_string(::getpid()))};
  std::stringstream text;
  {
    const SilencedStdout quiet;
    flexloop::pipeline::analyse_scene(scene, dir.path.string(), {f_min_hz, f_max_hz, points});
  }
  text << std::ifstream(dir.path / "analysis.json").rdbuf();
  return py::module_::import("json").attr("loads")(text.str());
}

// `flexloop sim`'s runs (online/sim/sim_command.hpp) as arrays: the logged run's time and
// signals (named as the columns of sim's --log), its RMS table and how the runs started.
struct SimResult {
  Eigen::VectorXd t;
  py::dict signals, rms, rms_command;
  std::string logged, start_off, start_on;
  bool controlled = false;
};

flexloop::artefact::LoopArtefact sim_loop(const py::object& scene_or_loop, double duration) {
  using flexloop::artefact::LoopArtefact;
  if (py::isinstance<LoopArtefact>(scene_or_loop)) {
    LoopArtefact a = scene_or_loop.cast<const LoopArtefact&>();
    a.duration_s = duration;
    return a;
  }
  const auto path = scene_or_loop.cast<std::string>();
  const py::gil_scoped_release unlocked;
  return flexloop::scene::load_loop(path, {.rate_hz = 0, .form = {}, .duration_s = duration});
}

// Arguments as sim's command line checks them, with its words.
void check_sim_arguments(double duration, const std::string& controller, const std::string& start) {
  using flexloop::common::InputError;
  if (!(std::isfinite(duration) && duration > 0))
    throw InputError("duration", "a finite number of seconds > 0, not " + std::to_string(duration));
  if (controller != "on" && controller != "off")
    throw InputError("controller", "'on' or 'off', not '" + controller + "'");
  if (start != "stationary" && start != "rest")
    throw InputError("start", "'stationary' or 'rest', not '" + start + "'");
}

SimResult sim(const py::object& scene_or_loop, double duration, const std::string& controller,
              const std::string& start, std::optional<std::uint64_t> seed) {
  namespace sim = flexloop::sim;
  check_sim_arguments(duration, controller, start);
  flexloop::artefact::LoopArtefact a = sim_loop(scene_or_loop, duration);
  if (seed) a.floor.seed = *seed;
  sim::SimRequest request;
  request.controller_on = controller == "on";
  request.start = start == "rest" ? sim::StartKind::kRest : sim::StartKind::kStationary;
  request.log = true;
  sim::BothRuns r;
  {
    const py::gil_scoped_release unlocked;
    r = sim::run_sim(a, request);
    sim::require_completed(a, r);
  }
  const bool on = sim::logs_controller_on(a, request);
  const auto log = (on ? r.on : r.off).log.matrix();
  const std::vector<std::string> header = sim::log_header(a);
  SimResult out;
  out.t = log.col(0);
  out.logged = on ? "on" : "off";
  out.start_off = r.start_off, out.start_on = r.start_on;
  out.controlled = r.controlled;
  for (std::size_t c = 1; c < header.size(); ++c)
    out.signals[py::str(header[c])] = Eigen::VectorXd(log.col(static_cast<Eigen::Index>(c)));
  for (const sim::RmsRow& row : sim::rms_table(a, r)) {
    py::dict d;
    d["unit"] = row.unit, d["off"] = row.off, d["on"] = row.on, d["change_db"] = row.change_db;
    out.rms[py::str(row.channel)] = d;
  }
  if (r.controlled)
    for (std::size_t i = 0; i < a.channels.actuators.size(); ++i)
      out.rms_command[py::str(a.channels.actuators[i].name)] =
          r.on.rms_command(static_cast<Eigen::Index>(i));
  return out;
}

// A campaign's samples and summary, as `flexloop campaign` writes samples.jsonl and summary.json.
struct CampaignResult {
  py::object plan, samples, summary;
};

// Every evaluation of the plan, `jobs` threads at once (each sample depends on the plan and its
// index alone: the bytes of `flexloop campaign run`, whatever computes it), in index order.
std::vector<nlohmann::json> plan_lines(const flexloop::campaign::PlanSamples& samples,
                                       long evaluations, int jobs) {
  std::vector<nlohmann::json> lines(static_cast<std::size_t>(evaluations));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(jobs));
  std::vector<std::thread> threads;
  for (int k = 0; k < jobs; ++k)
    threads.emplace_back([&, k] {
      try {
        for (long i = k; i < evaluations; i += jobs)
          lines[static_cast<std::size_t>(i)] = samples.line(i);
      } catch (...) {
        errors[static_cast<std::size_t>(k)] = std::current_exception();
      }
    });
  for (auto& t : threads) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  return lines;
}

CampaignResult campaign(const std::string& scene, const std::string& uncertain, long n,
                        const std::string& design, std::uint64_t seed, std::optional<int> jobs) {
  namespace campaign = flexloop::campaign;
  const int threads =
      jobs.value_or(std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
  if (threads < 1) throw flexloop::common::InputError("jobs", "at least 1");
  nlohmann::json plan, summary;
  std::vector<nlohmann::json> lines;
  {
    const py::gil_scoped_release unlocked;
    campaign::PlanRequest request;
    request.scene = scene, request.uncertain = uncertain, request.n = n;
    request.design = design, request.seed = seed;
    plan = campaign::make_plan(request);
    const campaign::PlanSamples samples(plan);
    lines = plan_lines(samples, plan.at("evaluations").get<long>(), threads);
    summary = campaign::campaign_summary(plan, lines);
  }
  const py::object loads = py::module_::import("json").attr("loads");
  py::list samples;
  for (const auto& line : lines) samples.append(loads(line.dump()));
  return {loads(plan.dump()), samples, loads(summary.dump())};
}

void bind_runs(py::module_& m) {
  py::class_<SimResult>(m, "SimResult",
                        "`flexloop sim`'s logged run and RMS table (doc/python.md).")
      .def_readonly("t", &SimResult::t)
      .def_readonly("signals", &SimResult::signals)
      .def_readonly("rms", &SimResult::rms)
      .def_readonly("rms_command", &SimResult::rms_command)
      .def_readonly("logged", &SimResult::logged)
      .def_readonly("start_off", &SimResult::start_off)
      .def_readonly("start_on", &SimResult::start_on)
      .def_readonly("controlled", &SimResult::controlled)
      .def("__repr__", [](const SimResult& r) {
        return "<flexloop.SimResult: " + std::to_string(r.t.size()) + " samples of " +
               std::to_string(py::len(r.signals)) + " signals, controller " + r.logged + ">";
      });
  m.def("sim", &sim, py::arg("scene_or_loop"), py::arg("duration"), py::arg("controller") = "on",
        py::arg("start") = "stationary", py::arg("seed") = py::none(),
        "Run a loop as `flexloop sim SCENE --duration D --controller C --start S --log ...`:\n"
        "both runs (controller off and on), the requested one logged. scene_or_loop: a scene or\n"
        "artefact file, or a Loop; seed: the floor's (default: the loop's).\n"
        "Example: flexloop.sim('tools/scenes/metrology_frame.toml', 1.0).rms");
  py::class_<CampaignResult>(m, "CampaignResult",
                             "A campaign's plan, samples and summary (doc/python.md).")
      .def_readonly("plan", &CampaignResult::plan)
      .def_readonly("samples", &CampaignResult::samples)
      .def_readonly("summary", &CampaignResult::summary)
      .def("__repr__", [](const CampaignResult& r) {
        return "<flexloop.CampaignResult: " + std::to_string(py::len(r.samples)) + " samples>";
      });
  m.def("campaign", &campaign, py::arg("scene"), py::arg("uncertain"), py::arg("n"),
        py::arg("design") = "lhs", py::arg("seed") = 1, py::arg("jobs") = py::none(),
        "A campaign as `flexloop campaign SCENE -u UNCERTAIN -n N --design D --seed S`: the\n"
        "plan, the samples (samples.jsonl's lines) and the summary (summary.json), computed on\n"
        "`jobs` threads (default: every core). Writes no files.\n"
        "Example: flexloop.campaign('tools/scenes/metrology_frame.toml',\n"
        "    'tools/scenes/metrology_frame_uncertain.toml', 20).summary");
}

void bind_loop(py::module_& m) {
  using flexloop::artefact::LoopArtefact;
  py::class_<LoopArtefact>(m, "Loop",
                           "A loop artefact (doc/loop_artefact.md): the discrete plant, its "
                           "channels, rate and controller, as `flexloop build` writes it.")
      .def_readonly("name", &LoopArtefact::name)
      .def_readonly("rate_hz", &LoopArtefact::rate_hz)
      .def_property_readonly(
          "method", [](const LoopArtefact& a) { return flexloop::artefact::to_string(a.method); })
      .def_property_readonly(
          "form", [](const LoopArtefact& a) { return flexloop::artefact::to_string(a.plant.form); })
      .def_property_readonly(
          "controller",
          [](const LoopArtefact& a) { return flexloop::artefact::to_string(a.controller); })
      .def_property_readonly("A", [](const LoopArtefact& a) { return a.plant.A; })
      .def_property_readonly("B", [](const LoopArtefact& a) { return a.plant.B; })
      .def_property_readonly("C", [](const LoopArtefact& a) { return a.plant.C; })
      .def_property_readonly("D", [](const LoopArtefact& a) { return a.plant.D; })
      .def_property_readonly("states", [](const LoopArtefact& a) { return a.plant.states; })
      .def_property_readonly("spectral_radius",
                             [](const LoopArtefact& a) { return a.plant.spectral_radius; })
      .def_property_readonly("disturbances",
                             [](const LoopArtefact& a) { return names(a.channels.disturbances); })
      .def_property_readonly("actuators",
                             [](const LoopArtefact& a) { return names(a.channels.actuators); })
      .def_property_readonly("performance",
                             [](const LoopArtefact& a) { return names(a.channels.performance); })
      .def_property_readonly("sensors",
                             [](const LoopArtefact& a) { return names(a.channels.sensors); })
      .def(
          "save",
          [](const LoopArtefact& a, const std::string& path) {
            flexloop::artefact::write_loop_artefact(path, a);
          },
          py::arg("path"), "Write the artefact (JSON), as `flexloop build -o PATH`.")
      .def("__repr__", [](const LoopArtefact& a) {
        return "<flexloop.Loop " + a.name + ": " + std::to_string(a.plant.states.size()) +
               " states at " + std::to_string(a.rate_hz) + " Hz, controller " +
               flexloop::artefact::to_string(a.controller) + ">";
      });
}

}  // namespace

PYBIND11_MODULE(flexloop, m) {
  m.doc() =
      "flexloop: a finite-element multibody model -> linearised, discretised plant -> loop.\n"
      "The command line's computations, numpy arrays in and out (doc/python.md).";
  py::register_exception<flexloop::common::InputError>(m, "InputError", PyExc_ValueError);
  // One BLAS thread, as the command line runs: its results to the bit (the thread count changes
  // the last bits of a factorisation), and no spinning OpenBLAS threads beside the caller's.
  flexloop::cli::set_blas_threads();

  py::class_<Linearised>(m, "Linearised",
                         "The continuous state space of `flexloop linearise` and the natural "
                         "frequencies of the dynamic coordinates.")
      .def_readonly("A", &Linearised::A)
      .def_readonly("B", &Linearised::B)
      .def_readonly("C", &Linearised::C)
      .def_readonly("D", &Linearised::D)
      .def_readonly("states", &Linearised::states)
      .def_readonly("inputs", &Linearised::inputs)
      .def_readonly("outputs", &Linearised::outputs)
      .def_readonly("natural_frequencies_hz", &Linearised::natural_frequencies_hz)
      .def("__repr__", [](const Linearised& l) {
        return "<flexloop.Linearised: " + std::to_string(l.A.rows()) + " states, " +
               std::to_string(l.B.cols()) + " inputs, " + std::to_string(l.C.rows()) + " outputs>";
      });

  m.def("linearise", &linearise, py::arg("model"), py::arg("inputs") = py::none(),
        py::arg("outputs") = py::none(),
        "Linearise a model file (TOML) about its operating point, as `flexloop linearise`.\n"
        "inputs, outputs: channel names (default: every prescribed coordinate as acc: and every\n"
        "actuated deformation as stress: in, every dynamic coordinate's pos: out).\n"
        "Example: flexloop.linearise('tools/models/cart.toml', ['acc:x.1'], ['pos:x.2']).A");

  bind_loop(m);
  m.def("build", &build, py::arg("scene"), py::arg("rate_hz") = py::none(),
        py::arg("form") = "dense",
        "Build a scene's loop artefact, as `flexloop build` (form: 'dense' or 'modal').\n"
        "Example: flexloop.build('tools/scenes/metrology_frame.toml').save('frame.json')");
  m.def(
      "load", [](const std::string& path) { return flexloop::artefact::read_loop_artefact(path); },
      py::arg("path"), "Read a loop artefact (JSON) written by `flexloop build` or Loop.save.");
  m.def("analyse", &analyse, py::arg("scene"), py::arg("f_min_hz") = 0.01,
        py::arg("f_max_hz") = 1000.0, py::arg("points") = 400,
        "The figures of `flexloop analyse SCENE` (analysis.json) as a dict.\n"
        "Example: flexloop.analyse('tools/scenes/metrology_frame.toml')['natural_frequencies_hz']");
  bind_runs(m);
}
