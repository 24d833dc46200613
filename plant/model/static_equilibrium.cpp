// SPDX-License-Identifier: BSD-3-Clause
#include "plant/model/static_equilibrium.hpp"

#include <stdexcept>
#include <string>

namespace flexloop::plant::model {

StaticEquilibrium static_equilibrium(const Model& m, int max_iterations) {
  const int nd = m.nd(), nq = m.nq();
  StaticEquilibrium r;
  r.op.q = reference_generalised(m);
  r.op.qd = Eigen::VectorXd::Zero(nq);
  r.op.qdd = Eigen::VectorXd::Zero(nq);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nq);
  // Scale for convergence: the size of the loads the struts carry.
  Eigen::VectorXd R = equations_of_motion_residual(m, r.op.q, zero, zero).head(nd);
  const double scale = std::max(R.norm(), 1.0);
  for (r.iterations = 0; r.iterations < max_iterations; ++r.iterations) {
    r.residual_norm = R.norm();
    if (r.residual_norm <= 1e-12 * scale) return r;
    const Linearisation lin = linearise(m, r.op);
    const Eigen::MatrixXd T = (lin.K + lin.N + lin.G).topLeftCorner(nd, nd);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(T);
    if (!lu.isInvertible())
      throw std::runtime_error(
          "static equilibrium: the tangent stiffness is singular (a "
          "mechanism, or exactly at buckling)");
    r.op.q.head(nd) -= lu.solve(R);
    R = equations_of_motion_residual(m, r.op.q, zero, zero).head(nd);
  }
  throw std::runtime_error("static equilibrium: no convergence in " +
                           std::to_string(max_iterations) + " Newton iterations (|R| = " +
                           std::to_string(R.norm()) + "); the load may exceed the buckling load");
}

}  // namespace flexloop::plant::model
