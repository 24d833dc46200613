// SPDX-License-Identifier: BSD-3-Clause
#include "controller/runtime/general_pi_controller.hpp"

#include <stdexcept>
#include <string>

namespace flexloop::controller::runtime {

template <typename Scalar>
GeneralPiController<Scalar> GeneralPiController<Scalar>::from_parameters(
    const artefact::PiParameters& p, Eigen::Index n) {
  const std::string who = "GeneralPiController";
  if (n < 1 || n > numeric::kMaxChannels)
    throw std::invalid_argument(who + ": " + std::to_string(n) + " channels; it takes 1 .. " +
                                std::to_string(numeric::kMaxChannels));
  const PiStepGains g = pi_step_gains(p, n, who);
  GeneralPiController c;
  c.G_f_ = numeric::padded_matrix<Scalar>(g.G_f);
  c.G_x_ = numeric::padded_matrix<Scalar>(g.G_x);
  c.G_x_inv_ = g.G_x_inv.cast<Scalar>();
  c.D22_ = g.D22.cast<Scalar>();
  c.identity_feedthrough_ = g.identity_feedthrough;
  c.a_ = static_cast<Scalar>(g.a);
  c.b_ = static_cast<Scalar>(g.b);
  c.delay_ = g.delay;
  c.history_.resize(n);
  c.u_min_ = g.u_min.cast<Scalar>();
  c.u_max_ = g.u_max.cast<Scalar>();
  c.f_ = c.u_ = Vector::Zero(n);
  c.s_ = c.v_ = c.g_ = Vector::Zero(numeric::padded_row_count<Scalar>(n));
  return c;
}

template class GeneralPiController<double>;
template class GeneralPiController<float>;

}  // namespace flexloop::controller::runtime
