// SPDX-License-Identifier: BSD-3-Clause
#include "controller/runtime/state_space_controller.hpp"

#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <stdexcept>
#include <string>

#include "controller/runtime/command_limits.hpp"

namespace flexloop::controller::runtime {

namespace {

const std::string kWho = "StateSpaceController";

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(kWho + ": " + what);
}

void require_size(const Eigen::MatrixXd& m, Eigen::Index rows, Eigen::Index cols,
                  const char* name) {
  require(m.rows() == rows && m.cols() == cols,
          std::string(name) + " is " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
              ", expected " + std::to_string(rows) + "x" + std::to_string(cols));
  require(m.allFinite(), std::string(name) + " has an entry that is not finite");
}

}  // namespace

template <typename Scalar>
StateSpaceController<Scalar> StateSpaceController<Scalar>::from_parameters(
    const artefact::StateSpaceParameters& p) {
  using M = Eigen::MatrixXd;
  const Eigen::Index nx = p.A.rows(), ns = p.B.cols(), nc = p.C.rows();
  constexpr int kMax = numeric::kMaxChannels;
  require(nx <= artefact::kMaxControllerStates, std::to_string(nx) + " states; it takes up to " +
                                                    std::to_string(artefact::kMaxControllerStates));
  require(ns >= 1 && ns <= kMax && nc >= 1 && nc <= kMax,
          std::to_string(ns) + " sensors and " + std::to_string(nc) +
              " actuators; each must be 1 .. " + std::to_string(kMax));
  require_size(p.A, nx, nx, "A");
  require_size(p.B, nx, ns, "B");
  require_size(p.C, nc, nx, "C");
  require_size(p.D, nc, ns, "D");
  const bool feedthrough = p.feedthrough.size() > 0 && !p.feedthrough.isZero(0);
  const M D22 = p.feedthrough.size() == 0 ? M::Zero(ns, nc) : p.feedthrough;
  require_size(D22, ns, nc, "the feedthrough D22");
  require(std::isfinite(p.dt) && p.dt > 0,
          "dt must be finite and > 0, got " + std::to_string(p.dt));
  require(p.feedthrough_delay >= 0 && p.feedthrough_delay <= artefact::kMaxFeedthroughDelay,
          "feedthrough_delay must be 0 .. " + std::to_string(artefact::kMaxFeedthroughDelay) +
              ", got " + std::to_string(p.feedthrough_delay));
  const CommandLimits limits = command_limits(p.u_min, p.u_max, nc, kWho);

  const M I = M::Identity(nc, nc);
  const Eigen::FullPivLU<M> loop(I - p.D * D22);
  require(loop.isInvertible(),
          "I - D D22 is singular: the loop through the sensors' feedthrough is ill-posed");
  M out(nc, nx + ns);
  if (nx > 0) out.leftCols(nx) = loop.solve(p.C);  // Eigen solves for no columns on a null pointer
  out.rightCols(ns) = loop.solve(p.D);
  M next(nx, nx + ns);
  next << p.A, p.B;
  // The bumpless start's least squares in the controller's state; none for a static gain (Eigen
  // cannot decompose a matrix without columns).
  const auto least_squares = [&](const M& rhs) -> Matrix {
    if (nx == 0) return Matrix(0, rhs.cols());
    return M(Eigen::CompleteOrthogonalDecomposition<M>(p.C).solve(rhs)).cast<Scalar>();
  };

  StateSpaceController c;
  c.nx_ = nx;
  c.ns_ = ns;
  c.out_ = numeric::padded_matrix<Scalar>(out);
  c.next_ = numeric::padded_matrix<Scalar>(next);
  c.next_u_ = numeric::padded_matrix<Scalar>(p.B * D22);
  c.F_ = numeric::padded_matrix<Scalar>(D22);
  c.start_u_ = least_squares(I - p.D * D22);
  c.start_f_ = least_squares(p.D);
  c.feedthrough_ = feedthrough;
  c.anti_windup_ = p.anti_windup;
  c.delay_ = p.feedthrough_delay;
  c.history_.resize(nc);
  c.w_.assign(static_cast<std::size_t>(nx + ns), Scalar(0));
  c.x_next_.assign(static_cast<std::size_t>(c.next_.rows()), Scalar(0));
  c.v_.assign(static_cast<std::size_t>(c.out_.rows()), Scalar(0));
  c.fu_.assign(static_cast<std::size_t>(c.F_.rows()), Scalar(0));
  c.u_min_ = limits.u_min.cast<Scalar>();
  c.u_max_ = limits.u_max.cast<Scalar>();
  c.u_ = Vector::Zero(nc);
  return c;
}

template class StateSpaceController<double>;
template class StateSpaceController<float>;

}  // namespace flexloop::controller::runtime
