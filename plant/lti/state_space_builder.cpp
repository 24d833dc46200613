#include "plant/lti/state_space_builder.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "plant/lti/solve_or_empty.hpp"
#include "plant/model/massless_condensation.hpp"
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
    throw common::InputError(what + " '" + name + "'",
                             "expected KIND:TARGET, e.g. force:x.3, stress:e1.4, acc:x.9, pos:x.3");
  return {name.substr(0, colon), name.substr(colon + 1)};
}

bool nonzero_col(const Eigen::MatrixXd& A, Eigen::Index j) {
  return A.col(j).cwiseAbs().maxCoeff() > 0.0;
}

}  // namespace

StateSpace build_state_space(const Model& m, const Linearisation& lin,
                             const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs, Condensation* condensation) {
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
  const Eigen::MatrixXd CDdd = CD.topLeftCorner(nd, nd), KNGdd = KNG.topLeftCorner(nd, nd);

  // Massless directions of Mdd, condensed statically (see the header): q_d = R p + H g, with the
  // state coordinates P (R_P = I). Without massless directions R = I, H = 0 and P = every
  // dynamic coordinate, and what follows is the plain A21 = -Mdd^-1 Kdd of doc/design.md §3.
  model::MasslessCondensation mc;
  if (nd > 0) {
    const std::vector<std::string> labels(m.generalised.begin(), m.generalised.begin() + nd);
    try {
      mc = model::condense_massless(Mdd, KNGdd, CDdd, {}, {}, labels);
    } catch (const std::invalid_argument& e) {
      throw common::InputError(
          m.file, std::string("the mass matrix of the dynamic coordinates: ") + e.what());
    }
  }
  const int nb = mc.massless_count, na = nd - nb;
  std::vector<int> P(static_cast<std::size_t>(na));
  Eigen::MatrixXd R = Eigen::MatrixXd::Identity(nd, na), H = Eigen::MatrixXd::Zero(nd, nd);
  if (nb == 0) {
    for (int j = 0; j < na; ++j) P[static_cast<std::size_t>(j)] = j;
  } else {
    // State coordinates: a pivoted QR of T^T with the columns weighted by sqrt(Mdd_ii) (unit-free:
    // sqrt(kg) times the coordinate's unit) picks n_a coordinates that carry mass and whose rows
    // of T are well conditioned.
    const Eigen::VectorXd w = Mdd.diagonal().cwiseMax(0.0).cwiseSqrt();
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(mc.T.transpose() * w.asDiagonal());
    for (int j = 0; j < na; ++j) P[static_cast<std::size_t>(j)] = qr.colsPermutation().indices()(j);
    std::sort(P.begin(), P.end());
    Eigen::MatrixXd TP(na, na);
    for (int j = 0; j < na; ++j) TP.row(j) = mc.T.row(P[static_cast<std::size_t>(j)]);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(TP.transpose());
    if (!(lu.rcond() > 1e-12))
      throw common::InputError(m.file,
                               "massless condensation: no set of dynamic coordinates describes "
                               "the massive directions (rows of T singular)");
    R = lu.solve(mc.T.transpose()).transpose();
    for (int j = 0; j < na; ++j)
      R.row(P[static_cast<std::size_t>(j)]) = Eigen::RowVectorXd::Unit(na, j);
    const Eigen::MatrixXd Kbb = mc.Z.transpose() * KNGdd * mc.Z;
    H = mc.Z * Kbb.partialPivLu().solve(mc.Z.transpose());
  }
  const Eigen::MatrixXd Mr = R.transpose() * Mdd * R;
  Eigen::LDLT<Eigen::MatrixXd> mdd(Mr);
  if (na > 0 && (mdd.info() != Eigen::Success || !mdd.isPositive()))
    throw common::InputError(m.file,
                             "the mass matrix of the dynamic coordinates is not positive definite");

  // Which prescribed-coordinate signals are inputs.
  std::vector<int> pos_in(nr, -1), vel_in(nr, -1), acc_in(nr, -1);
  Eigen::MatrixXd Bf = Eigen::MatrixXd::Zero(nd, nu);  // generalised forces of force/stress inputs
  std::vector<int> stress_in(m.ne(), -1);
  for (int j = 0; j < nu; ++j) {
    const auto [kind, target] = split(inputs[j], "input");
    const std::string place = "input '" + inputs[j] + "'";
    if (kind == "force") {
      const int i = m.coordinate_index(target);
      if (i < 0) throw common::InputError(place, "unknown nodal coordinate '" + target + "'");
      Bf.col(j) = lin.DFx.row(i).head(nd).transpose();
    } else if (kind == "stress") {
      const int k = m.deformation_index(target);
      if (k < 0) throw common::InputError(place, "unknown deformation '" + target + "'");
      if (m.deformation_roles[k] == model::DeformationRole::kRigid ||
          m.deformation_roles[k] == model::DeformationRole::kInert)
        throw common::InputError(
            place, "'" + target +
                       "' is rigid: an actuator stress needs a flexible or released deformation");
      Bf.col(j) = -lin.DFe.row(k).head(nd).transpose();
      stress_in[k] = j;
    } else if (kind == "pos" || kind == "vel" || kind == "acc") {
      const int i = qd_index(target);
      if (i < nd)
        throw common::InputError(place,
                                 "'" + target +
                                     "' is not a prescribed coordinate (prescribed: list it in "
                                     "[coordinates] prescribed)");
      auto& slot = kind == "pos" ? pos_in : kind == "vel" ? vel_in : acc_in;
      if (slot[i - nd] >= 0) throw common::InputError(place, "listed twice");
      slot[i - nd] = j;
    } else {
      throw common::InputError(place,
                               "unknown input kind '" + kind + "' (force, stress, pos, vel, acc)");
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
  for (const int i : P) states.push_back("pos:" + m.generalised[i]);
  for (const int i : P) states.push_back("vel:" + m.generalised[i]);
  std::vector<int> pos_state(nr, -1), vel_state(nr, -1);
  for (int r = 0; r < nr; ++r) {
    const std::string& label = m.generalised[nd + r];
    const bool need_pos = nonzero_col(KNGdr, r) || out_needs_pos[r];
    const bool need_vel = nonzero_col(CDdr, r) || out_needs_vel[r] || (need_pos && pos_in[r] < 0);
    const bool need_acc = nonzero_col(Mdr, r) || (need_vel && vel_in[r] < 0);
    const bool any = pos_in[r] >= 0 || vel_in[r] >= 0 || acc_in[r] >= 0;
    if (!any) continue;  // held at its operating value
    if (need_acc && acc_in[r] < 0)
      throw common::InputError("input 'pos:" + label + "'/'vel:" + label + "'",
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

  // The generalised force of inputs and prescribed coordinates on the dynamic rows,
  //   g = Bf u - Mdr qr'' - CDdr qr' - KNGdr qr,
  // and, for the massless part H g (Z^T Mdr = 0: M is positive semi-definite), its static part and
  // the rates that exist as signals: g' without Bf u', g'' without Bf u'' and CDdr qr'''.
  Eigen::MatrixXd g_z = Eigen::MatrixXd::Zero(nd, nz), g_u = Bf;
  Eigen::MatrixXd gs_z = Eigen::MatrixXd::Zero(nd, nz), gs_u = Bf;
  Eigen::MatrixXd g1_z = Eigen::MatrixXd::Zero(nd, nz), g1_u = Eigen::MatrixXd::Zero(nd, nu);
  Eigen::MatrixXd g2_z = Eigen::MatrixXd::Zero(nd, nz), g2_u = Eigen::MatrixXd::Zero(nd, nu);
  for (int r = 0; r < nr; ++r) {
    g_z -= Mdr.col(r) * r_acc[r].cz + CDdr.col(r) * r_vel[r].cz + KNGdr.col(r) * r_pos[r].cz;
    g_u -= Mdr.col(r) * r_acc[r].du + CDdr.col(r) * r_vel[r].du + KNGdr.col(r) * r_pos[r].du;
    if (nb == 0) continue;
    gs_z -= CDdr.col(r) * r_vel[r].cz + KNGdr.col(r) * r_pos[r].cz;
    gs_u -= CDdr.col(r) * r_vel[r].du + KNGdr.col(r) * r_pos[r].du;
    g1_z -= CDdr.col(r) * r_acc[r].cz + KNGdr.col(r) * r_vel[r].cz;
    g1_u -= CDdr.col(r) * r_acc[r].du + KNGdr.col(r) * r_vel[r].du;
    g2_z -= KNGdr.col(r) * r_acc[r].cz;
    g2_u -= KNGdr.col(r) * r_acc[r].du;
  }

  // q_d and q_d' as signals: q = R p + H g, q' = R p' + H g'.
  Eigen::MatrixXd q0_z = Eigen::MatrixXd::Zero(nd, nz), q0_u = Eigen::MatrixXd::Zero(nd, nu);
  Eigen::MatrixXd q1_z = Eigen::MatrixXd::Zero(nd, nz), q1_u = Eigen::MatrixXd::Zero(nd, nu);
  q0_z.leftCols(na) = R;
  q1_z.middleCols(na, na) = R;
  if (nb > 0) {
    q0_z += H * gs_z, q0_u += H * gs_u;
    q1_z += H * g1_z, q1_u += H * g1_u;
  }

  // Dynamics of p: R^T Mdd R p'' = R^T (g - Cdd q' - Kdd q).
  const Eigen::MatrixXd acc_z =
      solve_or_empty(mdd, R.transpose() * (g_z - CDdd * q1_z - KNGdd * q0_z));
  const Eigen::MatrixXd acc_u =
      solve_or_empty(mdd, R.transpose() * (g_u - CDdd * q1_u - KNGdd * q0_u));
  // q_d'' = R p'' + H g''.
  Eigen::MatrixXd q2_z = R * acc_z, q2_u = R * acc_u;
  if (nb > 0) q2_z += H * g2_z, q2_u += H * g2_u;

  if (condensation) {
    Condensation& c = *condensation;
    c = Condensation{};
    c.massless_count = nb;
    if (nb > 0) {
      std::vector<bool> is_state(static_cast<std::size_t>(nd), false);
      for (const int i : P) {
        is_state[static_cast<std::size_t>(i)] = true;
        c.state_coordinates.push_back(m.generalised[i]);
      }
      for (int i = 0; i < nd; ++i)
        if (!is_state[static_cast<std::size_t>(i)]) c.condensed.push_back(m.generalised[i]);
      c.damping_coupling = mc.damping_coupling;
      // Inputs whose rates the massless part would need but no signal carries.
      auto couples = [&](const Eigen::VectorXd& col) {
        const double n = col.norm();
        return n > 0.0 && (mc.Z.transpose() * col).norm() > 1e-9 * n;
      };
      auto drop = [&](int j) {
        if (j >= 0 && std::find(c.rate_terms_dropped.begin(), c.rate_terms_dropped.end(),
                                inputs[j]) == c.rate_terms_dropped.end())
          c.rate_terms_dropped.push_back(inputs[j]);
      };
      for (int j = 0; j < nu; ++j)
        if (couples(Bf.col(j))) drop(j);
      for (int r = 0; r < nr; ++r) {
        const bool has_vel = vel_in[r] >= 0 || vel_state[r] >= 0, has_acc = acc_in[r] >= 0;
        const bool k_couples = couples(KNGdr.col(r)), c_couples = couples(CDdr.col(r));
        if ((k_couples && (!has_vel || !has_acc)) || c_couples) {
          drop(pos_in[r]);
          drop(vel_in[r]);
          drop(acc_in[r]);
        }
      }
    }
  }

  StateSpace ss;
  ss.states = states;
  ss.inputs = inputs;
  ss.outputs = outputs;
  ss.A = Eigen::MatrixXd::Zero(nz, nz);
  ss.B = Eigen::MatrixXd::Zero(nz, nu);
  ss.A.block(0, na, na, na).setIdentity();
  ss.A.middleRows(na, na) = acc_z;
  ss.B.middleRows(na, na) = acc_u;
  for (int r = 0; r < nr; ++r) {
    if (pos_state[r] >= 0)
      ss.A.row(pos_state[r]) = r_vel[r].cz, ss.B.row(pos_state[r]) = r_vel[r].du;
    if (vel_state[r] >= 0)
      ss.A.row(vel_state[r]) = r_acc[r].cz, ss.B.row(vel_state[r]) = r_acc[r].du;
  }

  // Generalised-coordinate signals: q (position), q' (velocity), q'' (acceleration).
  auto q_signal = [&](int order, int i) -> Signal {
    if (i < nd) {
      if (order == 0) return {q0_z.row(i), q0_u.row(i)};
      if (order == 1) return {q1_z.row(i), q1_u.row(i)};
      return {q2_z.row(i), q2_u.row(i)};
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
      throw common::InputError(place, "unknown coordinate or deformation '" + target + "'");
    } else {
      throw common::InputError(
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
