#include "plant/lti/state_space_builder.hpp"

#include <sstream>

#include "plant/model/input_error.hpp"
#include "plant/model/released_model.hpp"

namespace flexloop::plant::lti {

namespace {

using model::Linearisation;
using model::Model;

// A signal as a linear function of state and input: s = cz . z + du . u.
struct Signal {
  Eigen::RowVectorXd cz, du;
};

struct Name {
  std::string kind, target;
};

Name split(const std::string& name, const std::string& what) {
  const auto colon = name.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == name.size())
    throw InputError(what + " '" + name + "'",
                     "expected KIND:TARGET, e.g. force:x.3, stress:e1.4, acc:x.9, pos:x.3");
  return {name.substr(0, colon), name.substr(colon + 1)};
}

bool nonzero_col(const Eigen::MatrixXd& A, Eigen::Index j) {
  return A.col(j).cwiseAbs().maxCoeff() > 0.0;
}

}  // namespace

StateSpace build_state_space(const Model& m, const Linearisation& lin,
                             const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs) {
  const int nd = m.nd(), nr = m.nr(), nu = static_cast<int>(inputs.size());
  auto qd_index = [&](const std::string& label) {  // index among all q, or -1
    for (int i = 0; i < m.nq(); ++i)
      if (m.generalised[i] == label) return i;
    return -1;
  };

  // Partitioned matrices.
  const Eigen::MatrixXd KNG = lin.K + lin.N + lin.G, CD = lin.C + lin.D;
  const Eigen::MatrixXd Mdd = lin.M.topLeftCorner(nd, nd);
  const Eigen::MatrixXd Mdr = lin.M.topRightCorner(nd, nr), CDdr = CD.topRightCorner(nd, nr),
                        KNGdr = KNG.topRightCorner(nd, nr);
  Eigen::LDLT<Eigen::MatrixXd> mdd(Mdd);
  {
    // Eigenvalues only for the check; the eigenvectors just to name the massless coordinates.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Mdd, Eigen::EigenvaluesOnly);
    const double top = es.eigenvalues().cwiseAbs().maxCoeff();
    if (!(es.eigenvalues().minCoeff() > 1e-12 * top)) {
      std::ostringstream os;
      os << "the mass matrix of the dynamic coordinates is singular: no mass is associated with ";
      const Eigen::VectorXd v =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Mdd).eigenvectors().col(0);
      bool first = true;
      for (int i = 0; i < nd; ++i)
        if (std::abs(v(i)) > 0.1) os << (first ? "" : ", ") << m.generalised[i], first = false;
      os << " (add mass, make them prescribed or dependent)";
      throw InputError(m.file, os.str());
    }
  }

  // Which prescribed-coordinate signals are inputs.
  std::vector<int> pos_in(nr, -1), vel_in(nr, -1), acc_in(nr, -1);
  Eigen::MatrixXd Bf = Eigen::MatrixXd::Zero(nd, nu);  // generalised forces of force/stress inputs
  std::vector<int> stress_in(m.ne(), -1);
  for (int j = 0; j < nu; ++j) {
    const auto [kind, target] = split(inputs[j], "input");
    const std::string place = "input '" + inputs[j] + "'";
    if (kind == "force") {
      const int i = m.coordinate_index(target);
      if (i < 0) throw InputError(place, "unknown nodal coordinate '" + target + "'");
      Bf.col(j) = lin.DFx.row(i).head(nd).transpose();
    } else if (kind == "stress") {
      const int k = m.deformation_index(target);
      if (k < 0) throw InputError(place, "unknown deformation '" + target + "'");
      if (m.deformation_roles[k] == model::DeformationRole::kRigid ||
          m.deformation_roles[k] == model::DeformationRole::kInert)
        throw InputError(
            place, "'" + target +
                       "' is rigid: an actuator stress needs a flexible or released deformation");
      Bf.col(j) = -lin.DFe.row(k).head(nd).transpose();
      stress_in[k] = j;
    } else if (kind == "pos" || kind == "vel" || kind == "acc") {
      const int i = qd_index(target);
      if (i < nd)
        throw InputError(place, "'" + target +
                                    "' is not a prescribed coordinate (prescribed: list it in "
                                    "[coordinates] prescribed)");
      auto& slot = kind == "pos" ? pos_in : kind == "vel" ? vel_in : acc_in;
      if (slot[i - nd] >= 0) throw InputError(place, "listed twice");
      slot[i - nd] = j;
    } else {
      throw InputError(place, "unknown input kind '" + kind + "' (force, stress, pos, vel, acc)");
    }
  }

  // Output dependence on prescribed positions/velocities, to decide integrator states.
  std::vector<bool> out_needs_pos(nr, false), out_needs_vel(nr, false);
  for (const auto& name : outputs) {
    const auto [kind, target] = split(name, "output");
    for (int r = 0; r < nr; ++r) {
      const int c = nd + r;
      if (const int i = m.coordinate_index(target); i >= 0) {
        if (kind == "pos") out_needs_pos[r] = out_needs_pos[r] || lin.DFx(i, c) != 0.0;
        if (kind == "vel") {
          out_needs_vel[r] = out_needs_vel[r] || lin.DFx(i, c) != 0.0;
          out_needs_pos[r] = out_needs_pos[r] || lin.Vx(i, c) != 0.0;
        }
        if (kind == "acc") {
          out_needs_vel[r] = out_needs_vel[r] || lin.Zx(i, c) != 0.0;
          out_needs_pos[r] = out_needs_pos[r] || lin.Wx(i, c) != 0.0;
        }
      } else if (const int k = m.deformation_index(target); k >= 0) {
        const Eigen::RowVectorXd de = lin.DFe.row(k);
        if (kind == "pos") out_needs_pos[r] = out_needs_pos[r] || de(c) != 0.0;
        if (kind == "stress") {
          out_needs_pos[r] = out_needs_pos[r] || (lin.S.row(k) * lin.DFe.col(c))(0) != 0.0 ||
                             (lin.Sd.row(k) * lin.Ved.col(c))(0) != 0.0;
          out_needs_vel[r] = out_needs_vel[r] || (lin.Sd.row(k) * lin.DFe.col(c))(0) != 0.0;
        }
      }
    }
  }

  // Integrator states for prescribed coordinates given by a higher derivative only.
  std::vector<std::string> states;
  for (int i = 0; i < nd; ++i) states.push_back("pos:" + m.generalised[i]);
  for (int i = 0; i < nd; ++i) states.push_back("vel:" + m.generalised[i]);
  std::vector<int> pos_state(nr, -1), vel_state(nr, -1);
  for (int r = 0; r < nr; ++r) {
    const std::string& label = m.generalised[nd + r];
    const bool need_pos = nonzero_col(KNGdr, r) || out_needs_pos[r];
    const bool need_vel = nonzero_col(CDdr, r) || out_needs_vel[r] || (need_pos && pos_in[r] < 0);
    const bool need_acc = nonzero_col(Mdr, r) || (need_vel && vel_in[r] < 0);
    const bool any = pos_in[r] >= 0 || vel_in[r] >= 0 || acc_in[r] >= 0;
    if (!any) continue;  // held at its operating value
    if (need_acc && acc_in[r] < 0)
      throw InputError("input 'pos:" + label + "'/'vel:" + label + "'",
                       "the dynamics depend on the acceleration of '" + label +
                           "': give it as acc:" + label + " (or all of acc, vel and pos)");
    if (need_vel && vel_in[r] < 0)
      vel_state[r] = static_cast<int>(states.size()), states.push_back("vel:" + label);
    if (need_pos && pos_in[r] < 0)
      pos_state[r] = static_cast<int>(states.size()), states.push_back("pos:" + label);
  }
  const int nz = static_cast<int>(states.size());

  // Signals of the prescribed coordinates.
  auto unit = [&](int n, int i) {
    Eigen::RowVectorXd v = Eigen::RowVectorXd::Zero(n);
    if (i >= 0) v(i) = 1.0;
    return v;
  };
  std::vector<Signal> r_pos(nr), r_vel(nr), r_acc(nr);
  for (int r = 0; r < nr; ++r) {
    r_pos[r] = {unit(nz, pos_state[r]), unit(nu, pos_in[r])};
    r_vel[r] = {unit(nz, vel_state[r]), unit(nu, vel_in[r])};
    r_acc[r] = {Eigen::RowVectorXd::Zero(nz), unit(nu, acc_in[r])};
  }

  // Dynamics: qd'' = Mdd^-1 [Bf u - Mdr qr'' - CD qd' ... - KNG q...].
  Eigen::MatrixXd rhs_z = Eigen::MatrixXd::Zero(nd, nz), rhs_u = Bf;
  rhs_z.leftCols(nd) -= KNG.topLeftCorner(nd, nd);
  rhs_z.middleCols(nd, nd) -= CD.topLeftCorner(nd, nd);
  for (int r = 0; r < nr; ++r) {
    rhs_z -= Mdr.col(r) * r_acc[r].cz + CDdr.col(r) * r_vel[r].cz + KNGdr.col(r) * r_pos[r].cz;
    rhs_u -= Mdr.col(r) * r_acc[r].du + CDdr.col(r) * r_vel[r].du + KNGdr.col(r) * r_pos[r].du;
  }
  const Eigen::MatrixXd acc_z = mdd.solve(rhs_z), acc_u = mdd.solve(rhs_u);

  StateSpace ss;
  ss.states = states;
  ss.inputs = inputs;
  ss.outputs = outputs;
  ss.A = Eigen::MatrixXd::Zero(nz, nz);
  ss.B = Eigen::MatrixXd::Zero(nz, nu);
  ss.A.block(0, nd, nd, nd).setIdentity();
  ss.A.middleRows(nd, nd) = acc_z;
  ss.B.middleRows(nd, nd) = acc_u;
  for (int r = 0; r < nr; ++r) {
    if (pos_state[r] >= 0)
      ss.A.row(pos_state[r]) = r_vel[r].cz, ss.B.row(pos_state[r]) = r_vel[r].du;
    if (vel_state[r] >= 0)
      ss.A.row(vel_state[r]) = r_acc[r].cz, ss.B.row(vel_state[r]) = r_acc[r].du;
  }

  // Generalised-coordinate signals: q (position), q' (velocity), q'' (acceleration).
  auto q_signal = [&](int order, int i) -> Signal {
    if (i < nd) {
      if (order == 0) return {unit(nz, i), Eigen::RowVectorXd::Zero(nu)};
      if (order == 1) return {unit(nz, nd + i), Eigen::RowVectorXd::Zero(nu)};
      return {acc_z.row(i), acc_u.row(i)};
    }
    const int r = i - nd;
    return order == 0 ? r_pos[r] : order == 1 ? r_vel[r] : r_acc[r];
  };
  // A linear combination sum_i w_i * q_i^(order).
  auto combine = [&](int order, const Eigen::RowVectorXd& w, Signal& s) {
    for (int i = 0; i < m.nq(); ++i) {
      if (w(i) == 0.0) continue;
      const Signal qi = q_signal(order, i);
      s.cz += w(i) * qi.cz;
      s.du += w(i) * qi.du;
    }
  };

  ss.C = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(outputs.size()), nz);
  ss.D = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(outputs.size()), nu);
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const auto [kind, target] = split(outputs[o], "output");
    const std::string place = "output '" + outputs[o] + "'";
    Signal s{Eigen::RowVectorXd::Zero(nz), Eigen::RowVectorXd::Zero(nu)};
    const int i = m.coordinate_index(target);
    const int k = m.deformation_index(target);
    if (i >= 0 && (kind == "pos" || kind == "vel" || kind == "acc")) {
      if (kind == "pos") combine(0, lin.DFx.row(i), s);
      if (kind == "vel") combine(1, lin.DFx.row(i), s), combine(0, lin.Vx.row(i), s);
      if (kind == "acc")
        combine(2, lin.DFx.row(i), s), combine(1, lin.Zx.row(i), s), combine(0, lin.Wx.row(i), s);
    } else if (k >= 0 && kind == "pos") {
      combine(0, lin.DFe.row(k), s);
    } else if ((i >= 0 && kind == "reaction") ||
               (k >= 0 && kind == "stress" &&
                (m.deformation_roles[k] == model::DeformationRole::kRigid ||
                 m.deformation_roles[k] == model::DeformationRole::kInert))) {
      // Equations of reaction by virtual work: release the coordinate into a prescribed one held
      // at its value; its generalised force is the support force (a rigid deformation's stress is
      // minus it, since d e_k / d q_k = 1).
      const model::Model released = model::release_to_prescribed(m, target);
      model::OperatingPoint op;
      op.q = model::reference_generalised(released);
      op.q.head(m.nq()) = lin.q;
      op.qd = Eigen::VectorXd::Zero(released.nq());
      op.qdd = Eigen::VectorXd::Zero(released.nq());
      op.qd.head(m.nq()) = lin.qd;
      op.qdd.head(m.nq()) = lin.qdd;
      op.sigma_a = lin.sigma_a;
      const model::Linearisation rl = model::linearise(released, op);
      const int ia = m.nq();
      const double sign = kind == "reaction" ? 1.0 : -1.0;
      combine(2, sign * rl.M.row(ia).head(m.nq()), s);
      combine(1, sign * (rl.C + rl.D).row(ia).head(m.nq()), s);
      combine(0, sign * (rl.K + rl.N + rl.G).row(ia).head(m.nq()), s);
      for (int j = 0; j < nu; ++j) {
        const auto [in_kind, in_target] = split(inputs[j], "input");
        if (in_kind == "force") s.du(j) -= sign * rl.DFx(m.coordinate_index(in_target), ia);
        if (in_kind == "stress") s.du(j) += sign * rl.DFe(m.deformation_index(in_target), ia);
      }
    } else if (k >= 0 && kind == "stress") {
      combine(0, lin.S.row(k) * lin.DFe + lin.Sd.row(k) * lin.Ved, s);
      combine(1, lin.Sd.row(k) * lin.DFe, s);
      if (stress_in[k] >= 0) s.du(stress_in[k]) += 1.0;
    } else if (i < 0 && k < 0) {
      throw InputError(place, "unknown coordinate or deformation '" + target + "'");
    } else {
      throw InputError(
          place,
          "unknown output kind '" + kind +
              "' for this target (pos/vel/acc/reaction of a nodal coordinate, pos/stress of a "
              "deformation)");
    }
    ss.C.row(static_cast<Eigen::Index>(o)) = s.cz;
    ss.D.row(static_cast<Eigen::Index>(o)) = s.du;
  }
  ss.validate();
  return ss;
}

}  // namespace flexloop::plant::lti
