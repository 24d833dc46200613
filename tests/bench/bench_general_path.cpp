// SPDX-License-Identifier: BSD-3-Clause
// Cost of one closed-loop step on the general path (any size, sized at start-up; issue 16,
// "Speed"): plant output, PI step, plant advance, as tests/support/closed_loop.hpp runs it.
//
//  - BM_MetrologyStep<path, form>: the metrology frame (12 states, 6 + 6 in, 6 + 6 out, PI on 6)
//    on the compiled fast path and on the general path, in the same process; the general ones
//    report ratio_to_compiled = (their ns) / (the compiled step's ns of the same form, measured
//    here). Target: within 3x.
//  - BM_LargeStep<form>/N: a lightly damped plant of N states (N/2 complex pole pairs), 6
//    disturbances + 6 actuators in, 6 performance + 6 sensors out, PI on 6 channels. Targets:
//    200 states modal <= 0.5 us, 2000 states modal <= 5 us. The modal plant is built in modal
//    coordinates (block-diagonal Lambda, random Bm and Cm, T = I): what to_modal_form gives,
//    without an eigendecomposition of a random 2000-state plant at set-up. The dense plant is the
//    same kind of system in a random basis (test::discrete_system). The dense form reports
//    bandwidth_ratio = (its ns per step) / (the ns to read the bytes of its matrices once, measured
//    here on an array of the same size read sequentially with eight independent packet
//    accumulators, so that loads, not add latency, bound it: the bandwidth of whichever cache level
//    holds them) and read_gbps, that read's rate. Target: <= 2.
// CPU time of the thread, as bench_runtime.cpp; compare figures of one run only.
#include <benchmark/benchmark.h>

#include <time.h>

#include <cmath>
#include <random>
#include <vector>

#include "controller/runtime/general_pi_controller.hpp"
#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/general_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/bench/bench_inputs.hpp"
#include "tests/support/closed_loop.hpp"
#include "tests/support/discrete_systems.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using bench::floor_samples;
using bench::kSamples;
using bench::thread_cpu_ns;

namespace {

artefact::PiParameters limited(artefact::PiParameters p) {
  p.u_min = Eigen::VectorXd::Constant(1, -2.0);
  p.u_max = Eigen::VectorXd::Constant(1, 2.0);
  return p;
}

// The general path's closed loop: the plant holds the PI's commands (its last nc inputs).
template <class Plant>
struct GeneralLoop {
  Plant plant;
  controller::runtime::GeneralPiController<double> pi;
  typename Plant::Input in;
  GeneralLoop(Plant p, const artefact::PiParameters& params)
      : plant(std::move(p)),
        pi(controller::runtime::GeneralPiController<double>::from_parameters(params,
                                                                             plant.held_inputs())),
        in(Plant::Input::Zero(plant.inputs())) {}
  double step(const Eigen::Matrix<double, 6, 1>& w) noexcept {
    const Eigen::Index nw = plant.sampled_inputs(), nc = plant.held_inputs();
    in.head(nw) = w;
    const auto& y = plant.output(in.head(nw));
    in.segment(nw, nc) = pi.step(y.segment(y.size() - nc, nc));
    plant.advance(in);
    return y(0);
  }
};

double g_compiled_ns[2] = {0, 0};  // dense, modal

template <bool kGeneral, bool kModal>
void BM_MetrologyStep(benchmark::State& state) {
  const auto& d = test::metrology().s.plant;
  const auto params = limited(test::metrology_pi_parameters());
  const auto& w = floor_samples();
  int k = 0;
  double sum = 0;
  const double t0 = thread_cpu_ns();
  if constexpr (kGeneral) {
    using Dense = plant::runtime::GeneralDensePlant<double>;
    using Modal = plant::runtime::GeneralModalPlant<double>;
    auto run = [&](auto loop) {
      for (auto _ : state) sum += loop.step(w[k++ & (kSamples - 1)]);
    };
    if constexpr (kModal)
      run(GeneralLoop<Modal>(Modal::from_modal_form(plant::lti::to_modal_form(d), 6), params));
    else
      run(GeneralLoop<Dense>(Dense::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D, 6), params));
  } else {
    using Pi = controller::runtime::PiController<double, 6>;
    auto run = [&](auto plant) {
      test::ClosedLoop<decltype(plant), Pi, 6> loop(plant, Pi::from_parameters(params));
      for (auto _ : state) sum += loop.step(w[k++ & (kSamples - 1)])(0);
    };
    if constexpr (kModal)
      run(plant::runtime::ModalPlant<double, 12, 12, 12, 6>::from_modal_form(
          plant::lti::to_modal_form(d)));
    else
      run(plant::runtime::DensePlant<double, 12, 12, 12, 6>::from_matrices(d.sys.A, d.sys.B,
                                                                           d.sys.C, d.sys.D));
  }
  benchmark::DoNotOptimize(sum);
  const double ns = (thread_cpu_ns() - t0) / static_cast<double>(state.iterations());
  if constexpr (kGeneral) {
    if (g_compiled_ns[kModal] > 0) state.counters["ratio_to_compiled"] = ns / g_compiled_ns[kModal];
  } else {
    g_compiled_ns[kModal] = ns;
  }
}
BENCHMARK_TEMPLATE(BM_MetrologyStep, false, false);
BENCHMARK_TEMPLATE(BM_MetrologyStep, true, false);
BENCHMARK_TEMPLATE(BM_MetrologyStep, false, true);
BENCHMARK_TEMPLATE(BM_MetrologyStep, true, true);

plant::lti::DiscreteStateSpace large_plant(int states) {
  std::vector<test::DiscretePole> poles;
  for (int i = 0; i < states / 2; ++i) poles.push_back({1.0 - 1e-4 * (1 + i % 11), 1e-3 * (1 + i)});
  return test::discrete_system(poles, 12, 12, 7);
}

// The modal form of N/2 lightly damped pairs (the same poles as large_plant), built directly.
plant::lti::ModalForm large_modal_form(int states) {
  const Eigen::Index n = states;
  plant::lti::ModalForm m;
  m.Lambda_minus_I = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i + 1 < n; i += 2) {
    const double r = 1.0 - 1e-4 * (1 + (i / 2) % 11), theta = 1e-3 * (1 + i / 2);
    const double a = r * std::cos(theta) - 1, b = r * std::sin(theta);
    m.Lambda_minus_I.block<2, 2>(i, i) << a, b, -b, a;
    m.block_sizes.push_back(2);
  }
  m.Lambda = m.Lambda_minus_I + Eigen::MatrixXd::Identity(n, n);
  std::mt19937 rng(7);
  m.B = test::random_matrix(rng, n, 12);
  m.C = test::random_matrix(rng, 12, n) / std::sqrt(static_cast<double>(n));
  m.D = Eigen::MatrixXd::Zero(12, 12);
  m.T = Eigen::MatrixXd::Identity(n, n);
  m.dt = 1e-4;
  return m;
}

artefact::PiParameters large_pi() {
  artefact::PiParameters p;
  p.K_P = 0.5 * Eigen::MatrixXd::Identity(6, 6);
  p.K_I = 50.0 * Eigen::MatrixXd::Identity(6, 6);
  p.dt = 1e-4;
  return limited(p);
}

// ns to read `bytes` of doubles once, sequentially (the same size as the plant's matrices, so the
// same cache level), best of 20. Eight independent accumulators of 8 doubles: one chain of adds
// would bound the read by its latency (one packet per 3-4 cycles), not by the loads.
double stream_ns(std::size_t bytes) {
  using Block = Eigen::Array<double, 64, 1>;
  const std::size_t blocks = bytes / sizeof(Block) + 1;
  std::vector<Block, Eigen::aligned_allocator<Block>> a(blocks, Block::Ones());
  double best = 1e300;
  Block sum = Block::Zero();
  for (int r = 0; r < 20; ++r) {
    const double t0 = thread_cpu_ns();
    for (int rep = 0; rep < 10; ++rep)
      for (const Block& b : a) sum += b;
    best = std::min(best, (thread_cpu_ns() - t0) / 10);
  }
  benchmark::DoNotOptimize(sum.sum());
  return best * static_cast<double>(bytes) / static_cast<double>(blocks * sizeof(Block));
}

template <bool kModal>
void BM_LargeStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto& w = floor_samples();
  int k = 0;
  double sum = 0;
  std::size_t bytes = 0;
  const double t0 = thread_cpu_ns();
  if constexpr (kModal) {
    using Modal = plant::runtime::GeneralModalPlant<double>;
    GeneralLoop<Modal> loop(Modal::from_modal_form(large_modal_form(n), 6), large_pi());
    for (auto _ : state) sum += loop.step(w[k++ & (kSamples - 1)]);
  } else {
    using Dense = plant::runtime::GeneralDensePlant<double>;
    const auto d = large_plant(n);
    GeneralLoop<Dense> loop(Dense::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D, 6),
                            large_pi());
    // [Ad - I; C Ad], [Bd; C Bd + ...] and D_s: what a step reads.
    bytes = sizeof(double) * static_cast<std::size_t>((n + 12) * n + (n + 12) * 12 + 12 * 6);
    for (auto _ : state) sum += loop.step(w[k++ & (kSamples - 1)]);
  }
  benchmark::DoNotOptimize(sum);
  const double ns = (thread_cpu_ns() - t0) / static_cast<double>(state.iterations());
  if (bytes > 0) {
    const double read_ns = stream_ns(bytes);
    state.counters["bandwidth_ratio"] = ns / read_ns;
    state.counters["read_gbps"] = static_cast<double>(bytes) / read_ns;
  }
}
BENCHMARK_TEMPLATE(BM_LargeStep, true)->Arg(200)->Arg(2000);
BENCHMARK_TEMPLATE(BM_LargeStep, false)->Arg(200);

}  // namespace
