// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/feedback_interconnection.hpp"

#include "plant/lti/solve_or_empty.hpp"

#include <stdexcept>
#include <string>

namespace flexloop::plant::lti {

namespace {

struct Blocks {
  Eigen::MatrixXd B1, B2, C1, C2, D11, D12, D21, D22;
};

Blocks split(const StateSpace& p, const StateSpace& c, LoopPartition part) {
  const Eigen::Index nw = part.disturbances, nz = part.performance;
  const Eigen::Index nu = p.nu() - nw, ny = p.ny() - nz;
  if (nw < 0 || nz < 0 || nu < 0 || ny < 0)
    throw std::invalid_argument("close_loop: the partition exceeds the plant's inputs/outputs");
  if (c.nu() != ny || c.ny() != nu)
    throw std::invalid_argument("close_loop: the controller has " + std::to_string(c.nu()) +
                                " inputs and " + std::to_string(c.ny()) +
                                " outputs; the plant has " + std::to_string(ny) +
                                " measured outputs and " + std::to_string(nu) + " actuator inputs");
  return {p.B.leftCols(nw),
          p.B.rightCols(nu),
          p.C.topRows(nz),
          p.C.bottomRows(ny),
          p.D.topLeftCorner(nz, nw),
          p.D.topRightCorner(nz, nu),
          p.D.bottomLeftCorner(ny, nw),
          p.D.bottomRightCorner(ny, nu)};
}

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

namespace {

// The command u = Ux x + Uc xc + Uw w that solves u = Cc xc + Dc (C2 x + D21 w + D22 u), and the
// measurement y = Yx x + Yc xc + Yw w it implies.
struct LoopSolution {
  Eigen::MatrixXd Ux, Uc, Uw, Yx, Yc, Yw;
};

LoopSolution solve_loop(const Blocks& b, const StateSpace& c) {
  const Eigen::Index nu = b.B2.cols();
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Eigen::MatrixXd::Identity(nu, nu) - c.D * b.D22);
  if (!lu.isInvertible())
    throw std::invalid_argument(
        "close_loop: I - Dc D22 is singular: the loop is ill-posed "
        "(an algebraic loop without a unique solution)");
  LoopSolution s{solve_or_empty(lu, c.D * b.C2),
                 solve_or_empty(lu, c.C),
                 solve_or_empty(lu, c.D * b.D21),
                 {},
                 {},
                 {}};
  s.Yx = b.C2 + b.D22 * s.Ux;
  s.Yc = b.D22 * s.Uc;
  s.Yw = b.D21 + b.D22 * s.Uw;
  return s;
}

}  // namespace

StateSpace close_loop(const StateSpace& p, const StateSpace& c, LoopPartition part) {
  p.validate();
  c.validate();
  const Blocks b = split(p, c, part);
  const LoopSolution l = solve_loop(b, c);
  const Eigen::Index nx = p.nx(), nc = c.nx();
  StateSpace t;
  t.A.resize(nx + nc, nx + nc);
  t.A << p.A + b.B2 * l.Ux, b.B2 * l.Uc, c.B * l.Yx, c.A + c.B * l.Yc;
  t.B.resize(nx + nc, part.disturbances);
  t.B << b.B1 + b.B2 * l.Uw, c.B * l.Yw;
  t.C.resize(part.performance, nx + nc);
  t.C << b.C1 + b.D12 * l.Ux, b.D12 * l.Uc;
  t.D = b.D11 + b.D12 * l.Uw;
  t.states = concat(p.states, c.states);
  t.inputs.assign(p.inputs.begin(), p.inputs.begin() + part.disturbances);
  t.outputs.assign(p.outputs.begin(), p.outputs.begin() + part.performance);
  t.validate();
  return t;
}

DiscreteStateSpace close_loop_sampled(const DiscreteStateSpace& pd, const DiscreteStateSpace& cd,
                                      LoopPartition part) {
  if (std::abs(pd.dt - cd.dt) > 1e-12 * pd.dt)
    throw std::invalid_argument("close_loop_sampled: plant and controller sample times differ");
  const StateSpace &p = pd.sys, &c = cd.sys;
  p.validate();
  c.validate();
  const Blocks b = split(p, c, part);
  // With the feedthrough removed, f = C2 x + D21 w and the loop solves as in continuous time.
  const LoopSolution l = solve_loop(b, c);
  const Eigen::Index nx = p.nx(), nc = c.nx(), nu = b.B2.cols(), nw = part.disturbances;
  const Eigen::Index n = nx + nc + nu;
  DiscreteStateSpace t{StateSpace{}, pd.dt, pd.method, pd.prewarp_hz, 0.0};
  StateSpace& s = t.sys;
  s.A.setZero(n, n);
  s.A.block(0, 0, nx, nx) = p.A + b.B2 * l.Ux;
  s.A.block(0, nx, nx, nc) = b.B2 * l.Uc;
  s.A.block(nx, 0, nc, nx) = c.B * l.Yx;
  s.A.block(nx, nx, nc, nc) = c.A + c.B * l.Yc;
  s.A.block(nx + nc, 0, nu, nx) = l.Ux;
  s.A.block(nx + nc, nx, nu, nc) = l.Uc;
  s.B.resize(n, nw);
  s.B << b.B1 + b.B2 * l.Uw, c.B * l.Yw, l.Uw;
  s.C.resize(part.performance, n);
  s.C << b.C1, Eigen::MatrixXd::Zero(part.performance, nc), b.D12;
  s.D = b.D11;
  s.states = concat(p.states, c.states);
  for (Eigen::Index i = nw; i < p.nu(); ++i) s.states.push_back("held:" + p.inputs[i]);
  s.inputs.assign(p.inputs.begin(), p.inputs.begin() + nw);
  s.outputs.assign(p.outputs.begin(), p.outputs.begin() + part.performance);
  s.validate();
  t.spectral_radius = spectral_radius(s.A);
  return t;
}

Eigen::MatrixXcd lft_closed_loop(const Eigen::MatrixXcd& G, const Eigen::MatrixXcd& C,
                                 LoopPartition part) {
  const Eigen::Index nw = part.disturbances, nz = part.performance;
  const Eigen::Index nu = G.cols() - nw, ny = G.rows() - nz;
  if (C.rows() != nu || C.cols() != ny)
    throw std::invalid_argument("lft_closed_loop: controller size does not match the partition");
  const Eigen::MatrixXcd G11 = G.topLeftCorner(nz, nw), G12 = G.topRightCorner(nz, nu),
                         G21 = G.bottomLeftCorner(ny, nw), G22 = G.bottomRightCorner(ny, nu);
  const Eigen::MatrixXcd I = Eigen::MatrixXcd::Identity(ny, ny);
  return G11 + G12 * C * (I - G22 * C).partialPivLu().solve(G21);
}

}  // namespace flexloop::plant::lti
