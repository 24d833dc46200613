// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Independent references in dynamic-size Eigen for the fixed-size runtime: a plant stepped from
// its matrices, and the PI controller in its general state-space form (Ac, Bc, Cc, Dc, closed
// around the sensors' feedthrough D22) with the algebraic loop solved by an LU every sample,
// not from precomputed gains.
#include <Eigen/Dense>

namespace flexloop::test {

struct PlantReference {
  Eigen::MatrixXd Ad, Bd, Cd, Dd;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(Ad.rows());

  Eigen::VectorXd output(const Eigen::VectorXd& u) const { return Cd * x + Dd * u; }
  void advance(const Eigen::VectorXd& u) { x = Ad * x + Bd * u; }
};

// u = (I - Dc D22)^-1 (Cc x + Dc f),  x+ = Ac x + Bc (f + D22 u),  f = y - D22 u_prev; when the
// command is clamped, the state is first moved to the one whose unsaturated law gives the clamped
// command: Cc x' = (I - Dc D22) u - Dc f. With anti_windup false it only clamps (and winds up).
struct PiReference {
  Eigen::MatrixXd Ac, Bc, Cc, Dc, D22;
  Eigen::VectorXd u_min, u_max;
  bool anti_windup = true;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(Ac.rows());
  Eigen::VectorXd u_prev = Eigen::VectorXd::Zero(Cc.rows());
  // The LUs of (I - Dc D22) and Cc, factored at the first step: the matrices stay as constructed,
  // and a solve with the same factors gives the same bits as factoring anew each sample.
  Eigen::MatrixXd loop{};
  Eigen::FullPivLU<Eigen::MatrixXd> loop_lu{}, state_lu{};

  Eigen::VectorXd step(const Eigen::VectorXd& y) {
    if (loop.size() == 0) {
      loop = Eigen::MatrixXd::Identity(D22.rows(), D22.rows()) - Dc * D22;
      loop_lu.compute(loop);
      state_lu.compute(Cc);
    }
    const Eigen::VectorXd f = y - D22 * u_prev;
    const Eigen::VectorXd v = loop_lu.solve(Cc * x + Dc * f);
    const Eigen::VectorXd u = v.cwiseMax(u_min).cwiseMin(u_max);
    if (anti_windup && u != v) x = state_lu.solve(loop * u - Dc * f);
    x = Ac * x + Bc * (f + D22 * u);
    u_prev = u;
    return u;
  }
};

}  // namespace flexloop::test
