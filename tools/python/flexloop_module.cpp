// The Python module `flexloop` (issue 55, 3; doc/python.md): the command line's computations as
// functions, numpy arrays in and out, the same code and so the same bits as the CLI. An input the
// CLI refuses raises flexloop.InputError (a ValueError) with the CLI's message (file:line).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "offline/pipeline/linearised_model.hpp"

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

}  // namespace

PYBIND11_MODULE(flexloop, m) {
  m.doc() =
      "flexloop: a finite-element multibody model -> linearised, discretised plant -> loop.\n"
      "The command line's computations, numpy arrays in and out (doc/python.md).";
  py::register_exception<flexloop::common::InputError>(m, "InputError", PyExc_ValueError);

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
}
