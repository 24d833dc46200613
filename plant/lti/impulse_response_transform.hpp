// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The frequency response of a sampled system from its impulse response, for a system seen only
// through what it outputs (a loop whose controller is compiled code: offline/pipeline/
// closed_loop_by_simulation.hpp):
//
//   H(e^{j w dt}) = sum_{k >= 0} h_k e^{-j w dt k},   h_k the response at sample k to a unit
//                                                     impulse at sample 0 (Markov parameters)
//
// accumulated block by block as the response is simulated: nothing is kept but the sums.
// Stopping at N samples leaves out at most sum_{k >= N} |h_k|; the caller bounds it from the
// decay it saw. Per block, the phasors e^{-j w dt k} start from the exact angle of the block's
// first sample (the product f dt k0 taken modulo one turn with its rounding error, by fma) and
// rotate inside the block (an error of about block length x 1e-16); then one real matrix
// product per part (real, imaginary).
#include <Eigen/Core>
#include <vector>

namespace flexloop::plant::lti {

class ImpulseResponseTransform {
 public:
  /// @throws std::invalid_argument unless dt > 0, the frequencies finite and outputs, inputs >= 1.
  ImpulseResponseTransform(std::vector<double> frequencies_hz, double dt, Eigen::Index outputs,
                           Eigen::Index inputs);

  /// Adds the responses to impulse `input` at samples k0 .. k0 + h.cols() - 1 (one column per
  /// sample, one row per output).
  /// @throws std::invalid_argument for an input out of range, a wrong row count or k0 < 0.
  void add(Eigen::Index input, long k0, const Eigen::Ref<const Eigen::MatrixXd>& h);

  /// Adds a tail that stays at `value` (one entry per output) from sample k0 on, the response of
  /// a pole at z = 1 (an undamped integrator): value z^-k0 / (1 - z^-1). Infinite at f = 0 (and
  /// at multiples of the sample rate) where value is not zero.
  /// @throws std::invalid_argument as add.
  void add_constant_tail(Eigen::Index input, long k0,
                         const Eigen::Ref<const Eigen::VectorXd>& value);

  /// One outputs x inputs matrix per frequency, in the order given: the sums so far.
  std::vector<Eigen::MatrixXcd> response() const;

 private:
  void check(Eigen::Index input, long k0, Eigen::Index rows) const;

  std::vector<double> cycles_per_sample_;  // f dt
  Eigen::Index outputs_;
  std::vector<Eigen::MatrixXd> real_, imaginary_;  // per input: outputs x frequencies
  Eigen::MatrixXd cos_, sin_;                      // the current block's phasors: samples x f
};

}  // namespace flexloop::plant::lti
