// SPDX-License-Identifier: BSD-3-Clause
// Cost of one closed-loop step of the metrology frame (issue 5, "Performance"; doc/design.md §6):
// plant output, PI step, plant advance, as tests/support/closed_loop.hpp runs it:
//   y_k = Cd x_k + Dd [w_k; u_{k-1}],  u_k = pi.step(y_k forces),  x_{k+1} = Ad x_k + Bd [w_k; u_k]
// for 12 states, 12 inputs, 12 outputs and 6 controller channels, with actuator limits of ±2 N
// (about 2 % of the samples saturate and run the anti-windup correction).
//
//  - BM_ClosedLoopStep<form, scalar>: the fixed-size runtime, dense or modal, double or float.
//  - BM_ClosedLoopStepNaive: the same step in dynamic-size Eigen (MatrixXd / VectorXd, temporaries
//    allocated every step) - the same-run baseline. Each fixed-size benchmark reports
//    speedup_vs_naive = (naive ns per step) / (its ns per step), the naive time measured in this
//    process (BM_ClosedLoopStepNaive's own result, or a 10^5-step measurement when filtered out).
//    Targets: <= 30 ns per step in double, >= 5x the naive step.
//  - BM_PiStep<scalar>: the PI controller's step alone (what the controller process computes).
//  - BM_TwoClosedLoopsInterleaved: two independent dense double loops, one step of each per
//    iteration (latency-bound steps would overlap; operation-bound ones add up).
//  - BM_Simulate10s<form, scalar>: 10 s of simulation at 10 kHz (10^5 steps) per iteration;
//    real_time_factor = 10 s / time. Target >= 1000.
// The counters use the thread's CPU time (as Google Benchmark's CPU column), so that other work on
// a shared machine does not count; the wall time is in the Time column. This VM's core clock
// wanders between about 2.1 and 3.3 GHz within minutes: compare figures of one run only.
// Floor accelerations are drawn before timing (4096 samples, reused cyclically).
#include <benchmark/benchmark.h>

#include <time.h>

#include <random>
#include <vector>

#include "controller/runtime/pi_controller.hpp"
#include "plant/lti/modal_form.hpp"
#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"
#include "tests/bench/bench_inputs.hpp"
#include "tests/support/closed_loop.hpp"
#include "tests/support/metrology.hpp"

using namespace flexloop;
using bench::floor_samples;
using bench::kSamples;
using bench::thread_cpu_ns;

namespace {

constexpr double kLimit = 2.0;  // N: actuator limit; ~2 % of the samples saturate

artefact::PiParameters pi_parameters() {
  auto p = test::metrology_pi_parameters();
  p.u_min = Eigen::VectorXd::Constant(1, -kLimit);
  p.u_max = Eigen::VectorXd::Constant(1, kLimit);
  return p;
}

// The step written the obvious way with dynamic sizes; same numbers, same law (the PI in its
// integral-command form, as controller/runtime/pi_controller.hpp).
struct NaiveLoop {
  Eigen::MatrixXd Ad, Bd, Cd, Dd, G_f, G_x;
  double a, b;
  Eigen::VectorXd lo, hi, x, s, u_prev;

  NaiveLoop() {
    const auto& d = test::metrology().s.plant.sys;
    const auto p = pi_parameters();
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(6, 6);
    Ad = d.A, Bd = d.B, Cd = d.C, Dd = d.D;
    G_f = -(I + p.K_P).inverse() * p.K_P;
    G_x = -(I + p.K_P).inverse() * p.K_I;
    a = std::exp(-p.leak_rad_s * p.dt);
    b = p.leak_rad_s > 0 ? (1 - a) / p.leak_rad_s : p.dt;
    lo = Eigen::VectorXd::Constant(6, -kLimit);
    hi = Eigen::VectorXd::Constant(6, kLimit);
    x = Eigen::VectorXd::Zero(12);
    s = u_prev = Eigen::VectorXd::Zero(6);
  }

  Eigen::VectorXd step(const Eigen::VectorXd& w) {
    Eigen::VectorXd in(12);
    in << w, u_prev;
    Eigen::VectorXd y = Cd * x + Dd * in;
    Eigen::VectorXd f = y.tail(6) - u_prev;
    Eigen::VectorXd p = G_f * f;
    Eigen::VectorXd v = p + s;
    Eigen::VectorXd u = v.cwiseMax(lo).cwiseMin(hi);
    s = a * (s + (u - v)) + b * (G_x * (f + u));
    u_prev = u;
    in.tail(6) = u;
    x = Ad * x + Bd * in;
    return y;
  }
};

const std::vector<Eigen::VectorXd>& naive_floor_samples() {
  static const auto w = [] {
    std::vector<Eigen::VectorXd> v;
    for (const auto& s : floor_samples<double>()) v.emplace_back(s);
    return v;
  }();
  return w;
}

double g_naive_ns = 0;  // ns per naive step, this process

double naive_ns_per_step() {
  if (g_naive_ns > 0) return g_naive_ns;
  NaiveLoop loop;
  const auto& w = naive_floor_samples();
  constexpr int kSteps = 100000;
  const double t0 = thread_cpu_ns();
  for (int k = 0; k < kSteps; ++k) benchmark::DoNotOptimize(loop.step(w[k % kSamples]));
  g_naive_ns = (thread_cpu_ns() - t0) / kSteps;
  return g_naive_ns;
}

void BM_ClosedLoopStepNaive(benchmark::State& state) {
  NaiveLoop loop;
  const auto& w = naive_floor_samples();
  int k = 0;
  const double t0 = thread_cpu_ns();
  for (auto _ : state) {
    Eigen::VectorXd y = loop.step(w[k++ & (kSamples - 1)]);
    benchmark::DoNotOptimize(y.data());
  }
  g_naive_ns = (thread_cpu_ns() - t0) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ClosedLoopStepNaive);

template <typename Scalar, template <typename, int, int, int, int> class Plant>
auto make_loop() {
  using P = Plant<Scalar, 12, 12, 12, 6>;  // holds the command
  using Pi = controller::runtime::PiController<Scalar, 6>;
  const auto& d = test::metrology().s.plant;
  P plant = [&] {
    if constexpr (std::is_same_v<P, plant::runtime::DensePlant<Scalar, 12, 12, 12, 6>>)
      return P::from_matrices(d.sys.A, d.sys.B, d.sys.C, d.sys.D);
    else
      return P::from_modal_form(plant::lti::to_modal_form(d));
  }();
  return test::ClosedLoop<P, Pi, 6>(plant, Pi::from_parameters(pi_parameters()));
}

template <typename Scalar, template <typename, int, int, int, int> class Plant>
void BM_ClosedLoopStep(benchmark::State& state) {
  auto loop = make_loop<Scalar, Plant>();
  const auto& w = floor_samples<Scalar>();
  int k = 0;
  const double t0 = thread_cpu_ns();
  for (auto _ : state) {
    auto y = loop.step(w[k++ & (kSamples - 1)]);
    benchmark::DoNotOptimize(y);
  }
  const double ns = (thread_cpu_ns() - t0) / static_cast<double>(state.iterations());
  state.counters["speedup_vs_naive"] = naive_ns_per_step() / ns;
}
BENCHMARK_TEMPLATE(BM_ClosedLoopStep, double, plant::runtime::DensePlant);
BENCHMARK_TEMPLATE(BM_ClosedLoopStep, float, plant::runtime::DensePlant);
BENCHMARK_TEMPLATE(BM_ClosedLoopStep, double, plant::runtime::ModalPlant);
BENCHMARK_TEMPLATE(BM_ClosedLoopStep, float, plant::runtime::ModalPlant);

// The PI alone, as the controller process runs it: measured forces from a table (the floor samples
// scaled to the sensors' 100 N range), one step per iteration.
template <typename Scalar>
void BM_PiStep(benchmark::State& state) {
  using Pi = controller::runtime::PiController<Scalar, 6>;
  Pi pi = Pi::from_parameters(pi_parameters());
  const auto& w = floor_samples<Scalar>();
  int k = 0;
  for (auto _ : state) {
    auto u = pi.step(Scalar(1e5) * w[k++ & (kSamples - 1)]);
    benchmark::DoNotOptimize(u);
  }
}
BENCHMARK_TEMPLATE(BM_PiStep, double);
BENCHMARK_TEMPLATE(BM_PiStep, float);

// Two independent loops stepped alternately: if a step were bound by the chain from one sample
// to the next alone, the pair would cost about one step; twice a step means the operations bound.
void BM_TwoClosedLoopsInterleaved(benchmark::State& state) {
  auto a = make_loop<double, plant::runtime::DensePlant>();
  auto b = make_loop<double, plant::runtime::DensePlant>();
  const auto& w = floor_samples<double>();
  int k = 0;
  for (auto _ : state) {
    auto ya = a.step(w[k & (kSamples - 1)]);
    auto yb = b.step(w[(k + kSamples / 2) & (kSamples - 1)]);
    ++k;
    benchmark::DoNotOptimize(ya);
    benchmark::DoNotOptimize(yb);
  }
}
BENCHMARK(BM_TwoClosedLoopsInterleaved);

template <typename Scalar, template <typename, int, int, int, int> class Plant>
void BM_Simulate10s(benchmark::State& state) {
  constexpr int kSteps = 100000;  // 10 s at 10 kHz
  const auto initial = make_loop<Scalar, Plant>();
  const auto& w = floor_samples<Scalar>();
  const double t0 = thread_cpu_ns();
  for (auto _ : state) {
    auto loop = initial;
    typename decltype(loop)::Output sum = decltype(sum)::Zero();
    for (int k = 0; k < kSteps; ++k) sum += loop.step(w[k & (kSamples - 1)]);
    benchmark::DoNotOptimize(sum);
  }
  const double ns = (thread_cpu_ns() - t0) / static_cast<double>(state.iterations());
  state.counters["real_time_factor"] = 10e9 / ns;
}
BENCHMARK_TEMPLATE(BM_Simulate10s, double, plant::runtime::DensePlant)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Simulate10s, double, plant::runtime::ModalPlant)
    ->Unit(benchmark::kMillisecond);

}  // namespace
