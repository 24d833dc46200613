// SPDX-License-Identifier: BSD-3-Clause
// The Python module `flexloop` (issue 55, 3; doc/python.md): the command line's computations as
// functions, numpy arrays in and out, the same code and so the same bits as the CLI. An input the
// CLI refuses raises flexloop.InputError (a ValueError) with the CLI's message (file:line).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "common/input_error.hpp"
#include "offline/pipeline/analyse_scene.hpp"
#include "offline/pipeline/linearised_model.hpp"
#include "offline/scene/loop_input.hpp"
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
}
