// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The superelement reduction's error, measured (issue 58 item 3): the machine's frequency
// response with each Craig-Bampton body against the same machine with the full FE body in its
// place, for named channels, and the natural frequencies of both.
//
// The full machine. The body's interior enters the machine only through its interface, so the
// full machine is the reduced one with the body's interface dynamic stiffness S_red(w) replaced by
// the full body's S_full(w) (the interior condensed exactly: plant/model/superelement_residual.hpp,
// from the reduction's moments of its unkept modes, to a stated bound). With force inputs f and
// position outputs x added on the interface coordinates, the reduced machine P gives the full
// one as the feedback f = -Delta x, Delta = S_full - S_red:
//   G_full = P_yu - P_yf Delta (I + P_xf Delta)^-1 P_xu,   G_red = P_yu.
// Cost per frequency: P at one frequency (as the analysis's own responses) and an n_b x n_b solve;
// no factorisation of the FE matrices.
//
// Damping. The plant's body damping (zeta on the reduced body's own modes) has no counterpart on
// the full body without all its modes, so both bodies get Rayleigh damping alpha M + beta K
// instead, which the reduction carries over exactly (T' (alpha M + beta K) T = alpha M_r +
// beta K_r), with the body's zeta (0.01 when it has none: an undamped response is infinite at
// its resonances) at the machine's lowest positive natural frequency and at the compared band's
// top (and at least 2 zeta sqrt(w_1 w_2) / (w_1 + w_2) between); the rest of the machine keeps
// its own damping. The figure is then the truncation's alone.
//
// Compared: the grid's frequencies up to the analysis's top and at most half the lowest cut-off
// (the band a reduction to f_c is meant for), every channel pair except outputs on modal
// amplitudes (the full body has none).
// Natural frequencies: the full machine's k-th is the fixed point of lambda = lambda_k(K_dd +
// T_b' Delta(lambda) T_b, M_dd), Delta undamped (Delta <= 0 falls with lambda: one crossing, from
// the reduced machine's lambda_k, an upper bound, downwards).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "plant/model/linearisation.hpp"
#include "plant/model/model.hpp"

namespace flexloop::plant::lti {

struct BodyComparison {
  std::string id;
  double cut_off_hz = 0;
  int modes_kept = 0, interface_dofs = 0;
  long full_dofs = 0;
  double zeta = 0;  ///< the damping ratio compared at (the body's, or 0.01)
  bool zeta_is_the_body_s = false;
  double low_hz = 0, high_hz = 0;  ///< where the Rayleigh damping gives zeta (the band's top)
  double alpha = 0, beta = 0;      ///< Rayleigh: alpha M + beta K (1/s, s)
};

struct PairError {
  bool compared = false;   ///< false: no response on the grid (identically zero)
  double relative = 0;     ///< max |G_red - G_full| / |G_full| over the compared grid
  double relative_hz = 0;  ///< where
  double of_peak = 0;      ///< max |G_red - G_full| / max |G_full|
  double of_peak_hz = 0;
};

struct ReductionError {
  std::vector<BodyComparison> bodies;
  std::vector<std::string> inputs, outputs;  ///< the compared channels
  std::vector<std::string> left_out;         ///< outputs not compared (on modal amplitudes)
  std::vector<PairError> pairs;              ///< outputs x inputs, row-major
  double band_hz = 0;                        ///< up_to_hz or half the lowest cut-off
  double lowest_hz = 0, highest_hz = 0;      ///< the grid frequencies compared
  int points = 0;
  double remainder = 0;  ///< the series' bound, relative to its first term, at the worst point
  std::vector<double> frequencies_hz;           ///< the compared grid points
  std::vector<Eigen::MatrixXcd> reduced, full;  ///< G_red, G_full there (outputs x inputs)
  Eigen::VectorXd reduced_hz, full_hz;          ///< undamped natural frequencies up to band_hz
  std::string frequencies_note;                 ///< why reduced_hz is empty, when it is

  const PairError& pair(std::size_t output, std::size_t input) const {
    return pairs[output * inputs.size() + input];
  }
};

/// At the frequencies up to `up_to_hz` and half the lowest cut-off. Empty `bodies` when the model
/// has no superelement. The model must have been read with the band set
/// (model::set_reduction_error_band_hz), so that each body carries its moments.
/// @throws flexloop::InputError from the state-space builder for unknown channels;
///         std::invalid_argument for a body without moments.
ReductionError reduction_error(const model::Model& m, const model::Linearisation& lin,
                               const std::vector<std::string>& inputs,
                               const std::vector<std::string>& outputs,
                               const std::vector<double>& frequencies_hz, double up_to_hz);

}  // namespace flexloop::plant::lti
