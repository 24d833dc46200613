// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The full body behind a reduced superelement, at one frequency (issue 58 item 3): its interface
// dynamic stiffness minus the reduced body's, both with the dynamic stiffness Z = a K - b M,
//   S_full - S_red = -(b^2 / a) sum_j z^j nu_j,   z = b / (a w_c^2),
// summed from the moments the reduction left (plant/superelement/residual_moments.hpp), with the
// bound on what the terms past the last leave out.
#include <Eigen/Dense>
#include <complex>

#include "plant/model/model.hpp"

namespace flexloop::plant::model {

struct ResidualStiffness {
  Eigen::MatrixXcd delta;  ///< S_full - S_red on the body's interface rows (n_b x n_b)
  double ratio = 0;        ///< |z|: below 1 the series converges
  double remainder = 0;    ///< bound on the terms left out, relative to the first (inf: |z| >= 1)
};

/// At (a, b); an empty delta (and ratio 0) for a body without moments.
ResidualStiffness residual_stiffness(const Superelement& body, std::complex<double> a,
                                     std::complex<double> b);

}  // namespace flexloop::plant::model
