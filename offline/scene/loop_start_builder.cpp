// SPDX-License-Identifier: BSD-3-Clause
#include "offline/scene/loop_start_builder.hpp"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "controller/design/pi_force_feedback.hpp"
#include "controller/design/sampled_loop_stability.hpp"
#include "numeric/stationary_covariance.hpp"
#include "offline/scene/schema_conversion.hpp"
#include "plant/lti/balanced_exponential.hpp"
#include "plant/lti/frequency_response.hpp"
#include "plant/lti/stable_covariance.hpp"
#include "plant/lti/vibration_criterion.hpp"

namespace flexloop::scene {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;

// The loop driven by unit white noise, its state [aug; h; s hist; u hist; xc; l] with
// aug = [floor filters (nw x order); floor noise (nw); sensor noise (ns); structure (plant states
// that are not the floor's)].
struct NoisyLoop {
  controller::design::SampledLoopModel loop;
  MatrixXd noise;        // Γ: the noise of the next sample enters the noise states
  MatrixXd performance;  // z_k as rows over the loop state
  Index floor_rows = 0, noise_rows = 0, structure_begin = 0, augmented = 0;
  std::vector<Index> structure;  // plant state of each structure row
};

std::vector<std::string> labels(Index n) {
  return std::vector<std::string>(n, "");
}

plant::lti::DiscreteStateSpace discrete(MatrixXd A, MatrixXd B, MatrixXd C, MatrixXd D, double dt) {
  plant::lti::DiscreteStateSpace d{
      {std::move(A), std::move(B), std::move(C), std::move(D), {}, {}, {}},
      dt,
      plant::lti::DiscretisationMethod::kZeroOrderHold,
      0,
      0};
  d.sys.states = labels(d.sys.A.rows());
  d.sys.inputs = labels(d.sys.B.cols());
  d.sys.outputs = labels(d.sys.C.rows());
  return d;
}

// Sensor noise of the chain as the linear loop sees it: sigma and the ADC's LSB²/12, referred to
// the signal before the gain error (the loop model applies 1 + eps to the whole signal).
double sensor_noise_rms(const artefact::SensorEffect& e) {
  if (!e.present) return 0;
  const double lsb = e.adc_bits > 0 ? e.adc_range / std::ldexp(1.0, e.adc_bits) : 0;
  return std::sqrt(e.noise_rms * e.noise_rms + lsb * lsb / 12) / (1 + e.gain_error);
}

// Closes the augmented plant g22 (states first, the noise of the next sample entering them as
// noise_in) with the artefact's controller, or none (open loop: a zero command), as the runtime
// loop runs it; performance: the performance outputs over g22's states (the held force's part is
// the plant's D).
void close_loop(const artefact::LoopArtefact& a, const plant::lti::DiscreteStateSpace& g22,
                const MatrixXd& noise_in, const MatrixXd& performance, bool closed, NoisyLoop& m) {
  const auto fail = [](const std::string& why) { throw std::invalid_argument(why); };
  const Index nc = a.actuators(), nz = a.performance(), ns = a.sensors(), na = g22.sys.nx();
  controller::design::SampledLoopHardware hw;
  plant::lti::DiscreteStateSpace controller;
  if (!closed) {
    controller =
        discrete(MatrixXd(0, 0), MatrixXd(0, ns), MatrixXd(nc, 0), MatrixXd::Zero(nc, ns), a.dt());
    hw.removed_feedthrough = MatrixXd::Zero(ns, nc);
  } else {
    const auto& e = a.effects;
    if (e.actuator.present) {
      hw.actuator_gain = e.actuator.gain;
      hw.actuator_lag_s = e.actuator.lag_s;
    }
    if (e.force_sensor.present) hw.sensor_gain_error = e.force_sensor.gain_error;
    if (a.controller == artefact::ControllerKind::kPiForceFeedback) {
      controller = controller::design::pi_discrete_controller(
          {a.pi.K_P, a.pi.K_I, {1, 1, a.pi.leak_rad_s}}, a.dt());
      hw.removed_feedthrough = a.pi.feedthrough;  // empty: the identity
      hw.feedthrough_delay = a.pi.feedthrough_delay;
    } else if (a.controller == artefact::ControllerKind::kStateSpace) {
      const auto& c = a.state_space;
      controller = discrete(c.A, c.B, c.C, c.D, a.dt());
      hw.removed_feedthrough = c.feedthrough.size() > 0 ? c.feedthrough : MatrixXd::Zero(ns, nc);
      hw.feedthrough_delay = c.feedthrough_delay;
    } else {
      fail("the artefact has no controller");
    }
  }
  m.loop = controller::design::sampled_loop_model(g22, controller, hw);
  const Index n = m.loop.A.rows();
  m.augmented = na;
  m.noise = MatrixXd::Zero(n, noise_in.cols());
  m.noise.topRows(na) = noise_in;
  m.performance = MatrixXd::Zero(nz, n);
  m.performance.leftCols(na) = performance;
  m.performance.middleCols(na, nc) = a.plant.D.topRows(nz).rightCols(nc);  // the held force h
}

// Throws std::invalid_argument saying why the loop has no stationary state.
NoisyLoop noisy_loop(const artefact::LoopArtefact& a, bool closed) {
  const auto fail = [](const std::string& why) { throw std::invalid_argument(why); };
  const auto& p = a.plant;
  const Index nx = p.A.rows(), nw = a.disturbances(), nc = a.actuators(), nz = a.performance(),
              ns = a.sensors();
  const bool vc = a.floor.spectrum != artefact::FloorSpectrum::kWhite;
  const Index nf = vc ? artefact::kFloorFilterOrder : 0;
  const auto floor = artefact::floor_states(a);
  if (!floor.empty() && !vc)
    fail("the plant has the floor's position as a state and a white floor has none");
  if (!floor.empty() && a.method != artefact::DiscretisationMethod::kZeroOrderHold)
    fail("the plant's floor states are other coordinates under method " +
         artefact::to_string(a.method));
  std::vector<bool> is_floor(static_cast<std::size_t>(nx), false);
  for (const auto& f : floor) is_floor[static_cast<std::size_t>(f.state)] = true;

  NoisyLoop m;
  for (Index i = 0; i < nx; ++i)
    if (!is_floor[static_cast<std::size_t>(i)]) m.structure.push_back(i);
  const Index n_structure = static_cast<Index>(m.structure.size());
  m.floor_rows = nf * nw;
  m.noise_rows = nw + ns;
  m.structure_begin = m.floor_rows + m.noise_rows;
  const Index na = m.structure_begin + n_structure, floor_noise = m.floor_rows,
              sensor_noise = floor_noise + nw;
  m.augmented = na;

  // The plant's state and the floor acceleration as rows over the augmented state.
  MatrixXd X = MatrixXd::Zero(nx, na), W = MatrixXd::Zero(nw, na);
  for (Index s = 0; s < n_structure; ++s) X(m.structure[s], m.structure_begin + s) = 1;
  for (const auto& f : floor) {
    X.block(f.state, f.channel * nf, 1, nf) = a.floor_filter.motion.row(f.motion_row);
    for (Index s : m.structure)
      if (p.A(f.state, s) != 0) fail("the floor's states depend on the structure's");
  }
  for (Index c = 0; c < nw; ++c) {
    if (vc) W.block(c, c * nf, 1, nf) = a.floor_filter.C;
    W(c, floor_noise + c) = vc ? a.floor_filter.D(0, 0) : a.floor.rms_mps2;
  }

  MatrixXd A = MatrixXd::Zero(na, na), B = MatrixXd::Zero(na, nc);
  for (Index c = 0; c < nw && vc; ++c) {
    A.block(c * nf, c * nf, nf, nf) = a.floor_filter.A;
    A.block(c * nf, floor_noise + c, nf, 1) = a.floor_filter.B;
  }
  const MatrixXd structure_rows =
      p.A(m.structure, Eigen::all) * X + p.B(m.structure, Eigen::seqN(0, nw)) * W;
  A.middleRows(m.structure_begin, n_structure) = structure_rows;
  B.middleRows(m.structure_begin, n_structure) = p.B(m.structure, Eigen::seqN(nw, nc));
  MatrixXd C = p.C.bottomRows(ns) * X + p.D.bottomRows(ns).leftCols(nw) * W;
  const double sigma = sensor_noise_rms(a.effects.force_sensor);
  for (Index i = 0; i < ns; ++i) C(i, sensor_noise + i) = sigma;
  const auto g22 =
      discrete(std::move(A), std::move(B), std::move(C), p.D.bottomRows(ns).rightCols(nc), a.dt());
  MatrixXd noise_in = MatrixXd::Zero(na, m.noise_rows);
  noise_in.middleRows(floor_noise, m.noise_rows).setIdentity();
  close_loop(a, g22, noise_in, p.C.topRows(nz) * X + p.D.topRows(nz).leftCols(nw) * W, closed, m);
  return m;
}

// The loop on the continuous floor: the VC filter driven by continuous unit white noise and the
// continuous plant, sampled exactly together (the noise's covariance over a sample by Van Loan's
// method), the actuator columns behind the DAC's hold as in the runtime. States: the floor
// filters, the structure (the floor's own position and velocity are the filter's motion), the
// sensor noise of the sample.
NoisyLoop continuous_floor_loop(const ScenePlant& sp, const artefact::LoopArtefact& a,
                                bool closed) {
  const auto fail = [](const std::string& why) { throw std::invalid_argument(why); };
  const plant::lti::StateSpace& g = sp.plant;
  if (a.floor.spectrum == artefact::FloorSpectrum::kWhite)
    fail("a white floor is band-limited by the sampling: it has no continuous counterpart");
  if (g.nx() != a.plant.A.rows())
    fail("the scene's plant is reduced: the continuous machine is another");
  const auto filter = plant::lti::design_floor_filter(
      plant::lti::criterion_band_velocity_rms(vibration_criterion(a.floor.spectrum)));
  if (filter.D.norm() != 0) fail("the floor filter has a feedthrough (infinite variance)");
  const MatrixXd motion = plant::lti::floor_motion_outputs(filter);
  const Index nx = g.nx(), nw = a.disturbances(), nc = a.actuators(), nz = a.performance(),
              ns = a.sensors(), nf = filter.nx();
  std::vector<bool> is_floor(static_cast<std::size_t>(nx), false);
  const auto floor = artefact::floor_states(a);
  for (const auto& f : floor) is_floor[static_cast<std::size_t>(f.state)] = true;
  std::vector<Index> structure;
  for (Index i = 0; i < nx; ++i)
    if (!is_floor[static_cast<std::size_t>(i)]) structure.push_back(i);
  const Index nS = static_cast<Index>(structure.size()), n = nf * nw + nS, na = n + ns;
  MatrixXd X = MatrixXd::Zero(nx, n), W = MatrixXd::Zero(nw, n);
  for (Index s = 0; s < nS; ++s) X(structure[s], nf * nw + s) = 1;
  for (const auto& f : floor) X.block(f.state, f.channel * nf, 1, nf) = motion.row(f.motion_row);
  for (Index c = 0; c < nw; ++c) W.block(c, c * nf, 1, nf) = filter.C;

  MatrixXd A = MatrixXd::Zero(n, n), noise = MatrixXd::Zero(n, nw);
  for (Index c = 0; c < nw; ++c) {
    A.block(c * nf, c * nf, nf, nf) = filter.A;
    noise.block(c * nf, c, nf, 1) = filter.B;
  }
  A.bottomRows(nS) = g.A(structure, Eigen::all) * X + g.B(structure, Eigen::seqN(0, nw)) * W;
  const double T = a.dt();
  // Zero-order hold of the actuators: expm([A B; 0 0] T) = [Ad Bd; 0 I].
  MatrixXd hold = MatrixXd::Zero(n + nc, n + nc);
  hold.topLeftCorner(n, n) = A * T;
  hold.block(nf * nw, n, nS, nc) = g.B(structure, Eigen::seqN(nw, nc)) * T;
  const MatrixXd held = plant::lti::balanced_exponential(hold);
  // Van Loan: expm([-A Q; 0 Aᵀ] T) = [.. F12; 0 F22], Qd = F22ᵀ F12.
  MatrixXd van_loan = MatrixXd::Zero(2 * n, 2 * n);
  van_loan.topLeftCorner(n, n) = -A * T;
  van_loan.topRightCorner(n, n) = noise * noise.transpose() * T;
  van_loan.bottomRightCorner(n, n) = A.transpose() * T;
  const MatrixXd F = plant::lti::balanced_exponential(van_loan);
  const MatrixXd Qd = F.bottomRightCorner(n, n).transpose() * F.topRightCorner(n, n);

  MatrixXd Ad = MatrixXd::Zero(na, na), Bd = MatrixXd::Zero(na, nc), C = MatrixXd::Zero(ns, na),
           noise_in = MatrixXd::Zero(na, na), performance = MatrixXd::Zero(nz, na);
  Ad.topLeftCorner(n, n) = held.topLeftCorner(n, n);
  Bd.topRows(n) = held.topRightCorner(n, nc);
  C.leftCols(n) = g.C.bottomRows(ns) * X + g.D.bottomRows(ns).leftCols(nw) * W;
  const double sigma = sensor_noise_rms(a.effects.force_sensor);
  for (Index i = 0; i < ns; ++i) C(i, n + i) = sigma;
  noise_in.topLeftCorner(n, n) = numeric::covariance_root(0.5 * (Qd + Qd.transpose()));
  noise_in.bottomRightCorner(ns, ns).setIdentity();
  performance.leftCols(n) = g.C.topRows(nz) * X + g.D.topRows(nz).leftCols(nw) * W;
  NoisyLoop m;
  close_loop(
      a, discrete(std::move(Ad), std::move(Bd), std::move(C), g.D.bottomRows(ns).rightCols(nc), T),
      noise_in, performance, closed, m);
  return m;
}

// A pole this close to the unit circle is on it: the rounding of the metrology frame's six-fold
// integrator pole is 3e-14 (balanced, controller/design/sampled_loop_stability.hpp), the slowest
// physical decay of a lightly damped mode (zeta = 1e-3 at 1 Hz) sampled at 1 MHz is 6e-9.
constexpr double kMarginalTolerance = 1e-9;

struct Covariance {
  MatrixXd factor;   // P = factor factor^T
  std::string note;  // what the modes on the unit circle do
  double sensitivity = 0;
};

// The stationary covariance of the loop without its modes on the unit circle. Those (the
// integrators of a force feedback without a leak) are split off along their invariant subspace
// (plant/lti/stable_covariance.hpp): the state's part on the other modes has a covariance; the
// part on the circle starts at zero, as from rest. Where the noise reaches it (an integrator of
// sensor noise) it drifts as a random walk from there.
Covariance stationary_covariance(const NoisyLoop& m) {
  const auto stable = plant::lti::stable_covariance(m.loop.A, m.noise, kMarginalTolerance);
  Covariance c;
  c.factor = stable.factor;
  c.sensitivity = stable.sensitivity;
  if (stable.on_circle > 0)
    c.note =
        std::to_string(stable.on_circle) + (stable.on_circle == 1 ? " mode" : " modes") +
        " on the unit circle (integrators or undamped modes) start at zero" +
        (stable.driven > 1e-8 ? "; the noise drives them: they drift from there as a random walk"
                              : "");
  return c;
}

// The distribution of the rest given the floor filters' states, from the factor of the joint
// covariance [R_r; R_f] [R_r; R_f]^T: with R_f = U S V^T (the floor's directions kept down to
// sqrt(1e-13) of the largest, i.e. its covariance's eigenvalues down to 1e-13), the gain is
// P_rf P_ff^+ = R_r V S^-1 U^T and the covariance R_r (I - V V^T) R_r^T, formed as C C^T with
// C = R_r - (R_r V) V^T: positive semidefinite by construction, where P_rr - gain P_fr loses
// its definiteness to cancellation when the rest's variance is far below the floor's.
struct Conditional {
  MatrixXd gain, covariance;
};

// C C^T, symmetric to the bit.
MatrixXd gram(const MatrixXd& c) {
  MatrixXd g = MatrixXd::Zero(c.rows(), c.rows());
  g.selfadjointView<Eigen::Lower>().rankUpdate(c);
  return g.selfadjointView<Eigen::Lower>();
}

Conditional conditional_on_floor(const MatrixXd& rest, const MatrixXd& floor) {
  if (floor.rows() == 0 || floor.cols() == 0)
    return {MatrixXd::Zero(rest.rows(), floor.rows()), gram(rest)};
  const Eigen::BDCSVD<MatrixXd> svd(floor, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  Index kept = 0;
  while (kept < sigma.size() && sigma(kept) > std::sqrt(1e-13) * sigma(0)) ++kept;
  const MatrixXd v = svd.matrixV().leftCols(kept);
  const MatrixXd rv = rest * v;
  const MatrixXd c = rest - rv * v.transpose();
  return {
      rv * sigma.head(kept).cwiseInverse().asDiagonal() * svd.matrixU().leftCols(kept).transpose(),
      gram(c)};
}

// The rows given the floor filters' states, in the layout of artefact/loop_start.hpp.
artefact::StationaryStart conditioned(const artefact::LoopArtefact& a, const NoisyLoop& m,
                                      const Covariance& c, bool closed) {
  const MatrixXd& R = c.factor;
  const Index nx = a.plant.A.rows(), nf = a.floor.spectrum == artefact::FloorSpectrum::kWhite
                                              ? 0
                                              : artefact::kFloorFilterOrder;
  const Index n = R.rows(), tail = n - m.augmented, nF = m.floor_rows;
  // Rest: the structure, then everything after the augmented plant.
  std::vector<Index> rest(m.structure.size());
  for (std::size_t s = 0; s < rest.size(); ++s) rest[s] = m.structure_begin + static_cast<Index>(s);
  for (Index t = 0; t < tail; ++t) rest.push_back(m.augmented + t);
  const auto [gain, covariance] = conditional_on_floor(R(rest, Eigen::all), R.topRows(nF));
  artefact::StationaryStart s;
  s.unavailable.clear();
  s.note = c.note;
  s.sensitivity = c.sensitivity;
  s.delay = closed ? (a.controller == artefact::ControllerKind::kPiForceFeedback
                          ? a.pi.feedthrough_delay
                          : a.state_space.feedthrough_delay)
                   : 0;
  s.actuator_lag = closed && a.effects.actuator.present && a.effects.actuator.lag_s > 0;
  s.controller_states =
      static_cast<int>(tail - a.actuators() - s.delay * a.sensors() -
                       (s.delay + 1) * a.actuators() - (s.actuator_lag ? a.actuators() : 0));
  const Index rows = nx + tail;
  // Layout row of each rest row: the structure's plant state, then the tail in order.
  std::vector<Index> row(rest.size());
  for (std::size_t s2 = 0; s2 < m.structure.size(); ++s2) row[s2] = m.structure[s2];
  for (Index t = 0; t < tail; ++t) row[m.structure.size() + static_cast<std::size_t>(t)] = nx + t;
  s.floor_gain = MatrixXd::Zero(rows, nF);
  s.covariance = MatrixXd::Zero(rows, rows);
  s.floor_gain(row, Eigen::all) = gain;
  s.covariance(row, row) = covariance;
  for (const auto& f : artefact::floor_states(a))
    s.floor_gain.block(f.state, f.channel * nf, 1, nf) = a.floor_filter.motion.row(f.motion_row);
  return s;
}

artefact::StationaryStart start_of(const artefact::LoopArtefact& a, bool closed) {
  try {
    const NoisyLoop m = noisy_loop(a, closed);
    return conditioned(a, m, stationary_covariance(m), closed);
  } catch (const std::invalid_argument& e) {
    artefact::StationaryStart s;
    s.unavailable = e.what();
    return s;
  }
}

}  // namespace

artefact::LoopStart stationary_loop_start(const artefact::LoopArtefact& a) {
  artefact::LoopStart s;
  s.open_loop = start_of(a, false);
  if (a.controller == artefact::ControllerKind::kFmu)
    s.closed_loop.unavailable = "an FMU controller cannot be seen into (its state is its own)";
  else if (a.controller != artefact::ControllerKind::kNone)
    s.closed_loop = start_of(a, true);
  else
    s.closed_loop.unavailable = "the loop has no controller";
  return s;
}

StationaryMoments stationary_moments(const artefact::LoopArtefact& a, bool closed) {
  const NoisyLoop m = noisy_loop(a, closed);
  const MatrixXd R = stationary_covariance(m).factor;
  return {(m.performance * R).rowwise().squaredNorm(),
          (m.loop.command * R).rowwise().squaredNorm()};
}

StationaryLoop stationary_loop(const artefact::LoopArtefact& a, bool closed) {
  NoisyLoop m = noisy_loop(a, closed);
  auto stable = plant::lti::stable_covariance(m.loop.A, m.noise, kMarginalTolerance);
  return {std::move(m.loop.A), std::move(m.noise), std::move(stable)};
}

StationaryMoments continuous_floor_moments(const ScenePlant& p, const artefact::LoopArtefact& a,
                                           bool closed) {
  const NoisyLoop m = continuous_floor_loop(p, a, closed);
  const MatrixXd R = stationary_covariance(m).factor;
  return {(m.performance * R).rowwise().squaredNorm(),
          (m.loop.command * R).rowwise().squaredNorm()};
}

}  // namespace flexloop::scene
