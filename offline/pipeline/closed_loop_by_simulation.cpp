// SPDX-License-Identifier: BSD-3-Clause
#include "offline/pipeline/closed_loop_by_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "controller/fmu/fmu_from_artefact.hpp"
#include "plant/lti/impulse_response_transform.hpp"

namespace flexloop::pipeline {

namespace {

// The artefact's dense plant split at the loop's partition
// (plant/lti/feedback_interconnection.hpp).
struct PlantBlocks {
  Eigen::MatrixXd A, B1, B2, C1, C2, D11, D12, D21, D22;
  explicit PlantBlocks(const artefact::LoopArtefact& a) {
    const Eigen::Index nw = a.disturbances(), nc = a.actuators(), nz = a.performance(),
                       ns = a.sensors();
    const auto& p = a.plant;
    A = p.A;
    B1 = p.B.leftCols(nw);
    B2 = p.B.rightCols(nc);
    C1 = p.C.topRows(nz);
    C2 = p.C.bottomRows(ns);
    D11 = p.D.topLeftCorner(nz, nw);
    D12 = p.D.topRightCorner(nz, nc);
    D21 = p.D.bottomLeftCorner(ns, nw);
    D22 = p.D.bottomRightCorner(ns, nc);
  }
};

// What one channel's run saw. A block's spread: its largest distance from its own last sample.
struct ChannelRun {
  long samples = 0;
  double peak = 0;              // largest |z|
  double spread = 0;            // the last block's spread of z, relative to the peak
  double constant = 0;          // largest |z| of the constant tail, relative to the peak
  double decay_per_sample = 0;  // of the spread, from the first block below 1e-6 to the last
  bool settled = false, diverged = false;
};

template <class Controller>
ChannelRun run_channel(const PlantBlocks& p, Controller& c, Eigen::Index j,
                       plant::lti::ImpulseResponseTransform& transform, const ImpulseSettings& s,
                       const std::function<void(Eigen::Index, long)>& progress) {
  using Vector = typename Controller::Vector;
  const Eigen::Index nx = p.A.rows(), nz = p.C1.rows(), ns = p.C2.rows(), nc = p.B2.cols();
  const long block = std::max(s.block_samples, 1L);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(nx), next(nx), z(nz);
  Vector y(ns), held = Vector::Zero(nc);
  Eigen::MatrixXd responses(nz, block), commands(nc, block);
  Eigen::VectorXd z_end = Eigen::VectorXd::Zero(nz), u_end = Eigen::VectorXd::Zero(nc);
  c.reset();
  ChannelRun r;
  double u_peak = 0, first_peak = 0, mid_spread = 0;
  long mid_samples = 0;
  while (r.samples < s.max_samples) {
    const long n = std::min(block, s.max_samples - r.samples), k0 = r.samples;
    for (long i = 0; i < n; ++i) {
      const double w = k0 + i == 0 ? s.amplitude : 0.0;
      y.noalias() = p.C2 * x + p.D22 * held;
      z.noalias() = p.C1 * x + p.D12 * held;
      next.noalias() = p.A * x;
      if (w != 0) {
        y += w * p.D21.col(j);
        z += w * p.D11.col(j);
        next += w * p.B1.col(j);
      }
      const Vector u = c.step(y);
      next.noalias() += p.B2 * u;
      x.swap(next);
      held = u;
      responses.col(i) = z / s.amplitude;
      commands.col(i) = u / s.amplitude;
    }
    const auto h = responses.leftCols(n), v = commands.leftCols(n);
    transform.add(j, k0, h);
    r.samples += n;
    const double z_block = h.cwiseAbs().maxCoeff(), u_block = v.cwiseAbs().maxCoeff();
    if (k0 == 0) first_peak = std::max(z_block, u_block);
    r.peak = std::max(r.peak, z_block);
    u_peak = std::max(u_peak, u_block);
    // Settled: within the block and since the last block's end, z and u moved less than the
    // tolerance (to zero, or to a constant an undamped integrator holds).
    const double z_spread = std::max((h.colwise() - h.col(n - 1)).cwiseAbs().maxCoeff(),
                                     (z_end - h.col(n - 1)).cwiseAbs().maxCoeff());
    const double u_spread = std::max((v.colwise() - v.col(n - 1)).cwiseAbs().maxCoeff(),
                                     (u_end - v.col(n - 1)).cwiseAbs().maxCoeff());
    z_end = h.col(n - 1);
    u_end = v.col(n - 1);
    r.spread = r.peak > 0 ? z_spread / r.peak : 0.0;
    if (mid_samples == 0 && k0 > 0 && r.spread <= 1e-6) {
      mid_samples = r.samples;
      mid_spread = r.spread;
    }
    if (progress) progress(j, r.samples);
    if (!std::isfinite(z_block) || !std::isfinite(u_block) ||
        std::max(z_block, u_block) > 1e12 * first_peak) {
      r.diverged = true;
      return r;
    }
    if (k0 > 0 && z_spread <= s.decay_tolerance * r.peak &&
        u_spread <= s.decay_tolerance * u_peak) {
      r.settled = true;
      break;
    }
  }
  // What stays is carried to infinity analytically (plant::lti::ImpulseResponseTransform).
  transform.add_constant_tail(j, r.samples, z_end);
  r.constant = r.peak > 0 ? z_end.cwiseAbs().maxCoeff() / r.peak : 0.0;
  if (mid_spread > 0 && r.spread > 0 && r.samples > mid_samples)
    r.decay_per_sample =
        std::pow(r.spread / mid_spread, 1.0 / static_cast<double>(r.samples - mid_samples));
  return r;
}

}  // namespace

ClosedLoopBySimulation closed_loop_by_simulation(
    const artefact::LoopArtefact& a, const std::vector<double>& frequencies_hz,
    const ImpulseSettings& s, const std::function<void(Eigen::Index, long)>& progress) {
  const PlantBlocks p(a);
  plant::lti::ImpulseResponseTransform transform(frequencies_hz, a.dt(), a.performance(),
                                                 a.disturbances());
  ClosedLoopBySimulation result;
  result.decayed = true;
  controller::fmu::with_any_controller<double>(a, [&](auto&& c) {
    for (Eigen::Index j = 0; j < a.disturbances(); ++j) {
      const ChannelRun r = run_channel(p, c, j, transform, s, progress);
      // A controller FMU's failure ends the measurement; its log goes to stderr.
      const controller::runtime::ControllerReport report = c.report();
      for (const std::string& m : report.messages) std::fprintf(stderr, "%s\n", m.c_str());
      if (!report.failure.empty()) {
        result.controller_failure = report.failure;
        return;
      }
      result.samples = std::max(result.samples, r.samples);
      result.decayed = result.decayed && r.settled;
      result.diverged = result.diverged || r.diverged;
      if (r.diverged) return;
      result.tail = std::max(result.tail, r.spread);
      result.constant_tail = std::max(result.constant_tail, r.constant);
      result.decay_per_sample = std::max(result.decay_per_sample, r.decay_per_sample);
      result.truncation_bound =
          std::max(result.truncation_bound, r.decay_per_sample < 1
                                                ? r.spread / (1 - r.decay_per_sample)
                                                : std::numeric_limits<double>::infinity());
    }
  });
  if (result.controller_failure.empty() && !result.diverged) result.response = transform.response();
  return result;
}

}  // namespace flexloop::pipeline
