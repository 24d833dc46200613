// SPDX-License-Identifier: BSD-3-Clause
// A controller FMU against the built-in PI (issue 33), in one run: the metrology frame's
// closed-loop step with the compiled PI and with the same law as the fixture FMU
// (tools/fmu/pi_force_feedback: fmi2SetReal, fmi2DoStep, fmi2GetReal per sample), and the FMU's
// step split into its three calls and fmi2DoStep alone, so that the FMI calls' own cost shows
// beside the FMU's computation.
//   taskset -c 0 build/bench/tests/bench/bench_fmu --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include "controller/fmu/fmu_archive.hpp"
#include "controller/fmu/fmu_controller.hpp"
#include "controller/fmu/fmu_description.hpp"
#include "controller/fmu/fmu_library.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "tests/bench/bench_inputs.hpp"
#include "tests/fmu/fmu_fixture.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using bench::floor_samples;
using bench::kSamples;

namespace {

using Plant = plant::runtime::DensePlant<double, 12, 12, 12, 6>;  // holds the command
using Pi = controller::runtime::PiController<double, 6>;

Plant metrology_plant() {
  const auto& d = test::metrology().s.plant;
  return Plant::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
}

controller::fmu::FmuController pi_fmu() {
  return controller::fmu::FmuController::from_settings(
      test::pi_fmu_settings(test::metrology_pi_parameters(), test::pi_fmu_path()));
}

// The closed-loop step of tests/support/closed_loop.hpp, for any controller.
template <class Controller>
void closed_loop(benchmark::State& state, Controller controller) {
  Plant plant = metrology_plant();
  Plant::Input in = Plant::Input::Zero();
  const auto& w = floor_samples<double>();
  int k = 0;
  for (auto _ : state) {
    const auto& wk = w[k++ & (kSamples - 1)];
    in.head<6>() = wk;
    const Plant::Output y = plant.output(wk);
    in.tail<6>() = controller.step(y.tail<6>());
    plant.advance(in);
    benchmark::DoNotOptimize(in);
  }
}

void BM_ClosedLoopStepBuiltinPi(benchmark::State& state) {
  closed_loop(state, Pi::from_parameters(test::metrology_pi_parameters()));
}
BENCHMARK(BM_ClosedLoopStepBuiltinPi);

void BM_ClosedLoopStepFmuPi(benchmark::State& state) {
  closed_loop(state, pi_fmu());
}
BENCHMARK(BM_ClosedLoopStepFmuPi);

// The FMU's calls alone, on sensor values from a table: all three, and fmi2DoStep alone.
template <bool kAllThree>
void BM_FmuCalls(benchmark::State& state) {
  const std::string file = test::pi_fmu_path();
  const controller::fmu::FmuDirectory dir(file);
  const auto description = controller::fmu::read_fmu_description(dir.path(), file);
  const controller::fmu::FmuLibrary library(dir.path(), description.model_identifier, file);
  const auto& f = library.calls();
  const fmi2CallbackFunctions callbacks{nullptr, nullptr, nullptr, nullptr, nullptr};
  const std::string resources = "file://" + (dir.path() / "resources").string();
  fmi2Component c = f.instantiate("bench", fmi2CoSimulation, description.guid.c_str(),
                                  resources.c_str(), &callbacks, fmi2False, fmi2False);
  f.setup_experiment(c, fmi2False, 0, 0, fmi2False, 0);
  f.enter_initialization_mode(c);
  f.exit_initialization_mode(c);
  std::array<fmi2ValueReference, 6> in{}, out{};
  for (unsigned i = 0; i < 6; ++i) {
    in[i] = description.real("y" + std::to_string(i + 1), "input", file).value_reference;
    out[i] = description.real("u" + std::to_string(i + 1), "output", file).value_reference;
  }
  const auto& w = floor_samples<double>();
  std::array<double, 6> u{};
  int k = 0;
  double t = 0;
  for (auto _ : state) {
    const auto& y = w[k++ & (kSamples - 1)];
    if constexpr (kAllThree) f.set_real(c, in.data(), 6, y.data());
    f.do_step(c, t, 1e-4, fmi2True);
    if constexpr (kAllThree) f.get_real(c, out.data(), 6, u.data());
    t += 1e-4;
    benchmark::DoNotOptimize(u);
  }
  f.terminate(c);
  f.free_instance(c);
}
BENCHMARK_TEMPLATE(BM_FmuCalls, true)->Name("BM_FmuSetDoStepGet");
BENCHMARK_TEMPLATE(BM_FmuCalls, false)->Name("BM_FmuDoStepOnly");

}  // namespace
