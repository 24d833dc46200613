// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The offline model of a loop (plant/lti's sampled plant or closed loop w -> [z; ...]) stepped
// with an artefact's own floor draws, from the floor's start (the plant's floor states where the
// floor generator starts, as the runtime sets them): what `flexloop sim` must reproduce.
#include <Eigen/Core>

#include "artefact/loop_artefact.hpp"
#include "online/sim/loop_hardware.hpp"
#include "tests/support/dynamic_reference.hpp"

namespace flexloop::test {

/// The RMS of the model's first nz outputs over `steps` samples.
inline Eigen::VectorXd reference_rms(const artefact::LoopArtefact& a, PlantReference model,
                                     Eigen::Index nz, long steps) {
  struct StateOf {  // what sim::plant_at_floor_start reads and writes
    using State = Eigen::VectorXd;
    Eigen::VectorXd x;
    State state() const { return x; }
    void set_state(const State& v) { x = v; }
  };
  return sim::with_floor<Eigen::Dynamic>(a, [&](auto floor) {
    model.x = sim::plant_at_floor_start(StateOf{model.x}, floor, a).x;
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(nz);
    for (long k = 0; k < steps; ++k) {
      const Eigen::VectorXd w = floor.step();
      sum += model.output(w).topRows(nz).cwiseAbs2();
      model.advance(w);
    }
    return Eigen::VectorXd((sum / static_cast<double>(steps)).cwiseSqrt());
  });
}

/// The largest |a_i - b_i| / |b_i|.
inline double worst_relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return ((a - b).cwiseAbs().array() / b.cwiseAbs().array()).maxCoeff();
}

}  // namespace flexloop::test
