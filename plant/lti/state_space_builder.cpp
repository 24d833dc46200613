// SPDX-License-Identifier: BSD-3-Clause
#include "plant/lti/state_space_builder.hpp"

#include <algorithm>
#include <array>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"
#include "plant/lti/solve_or_empty.hpp"
#include "plant/model/massless_condensation.hpp"
#include "plant/model/released_model.hpp"

// The construction of doc/design.md §3 "State space", one step per function: partition the
// linearised equations, condense their massless directions, select the inputs, select the
// outputs (and with them the integrator states), the state equations (A, B), the output equations
// (C) and their feedthrough (D). build_state_space, at the end, runs the steps in that order.
namespace flexloop::plant::lti {

namespace {

using model::Linearisation;
using model::Model;

// A signal as a linear function of state and input: s = cz . z + du . u.
struct Signal {
  Eigen::RowVectorXd cz, du;
};

// Several signals, one per row: s = Sz z + Su u (the members z = Sz, u = Su).
struct Signals {
  Eigen::MatrixXd z, u;
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

bool is_rigid(const Model& m, int k) {
  return m.deformation_roles[k] == model::DeformationRole::kRigid ||
         m.deformation_roles[k] == model::DeformationRole::kInert;
}

// The index of a generalised coordinate among all q (dynamic first, then prescribed), or -1.
int generalised_index(const Model& m, const std::string& label) {
  for (int i = 0; i < m.nq(); ++i)
    if (m.generalised[i] == label) return i;
  return -1;
}

// The row vector of n zeros with a 1 at i (none when i < 0: a signal that is not there).
Eigen::RowVectorXd unit(int n, int i) {
  Eigen::RowVectorXd v = Eigen::RowVectorXd::Zero(n);
  if (i >= 0) v(i) = 1.0;
  return v;
}

// The dynamic rows of the linearised equations, by dynamic (d) and prescribed (r) columns:
//   Mdd q_d'' + CDdd q_d' + KNGdd q_d = g - Mdr qr'' - CDdr qr' - KNGdr qr,
// with CD = C̄ + D̄ and KNG = K̄ + N̄ + Ḡ.
struct Partition {
  int nd = 0, nr = 0;
  Eigen::MatrixXd Mdd, CDdd, KNGdd, Mdr, CDdr, KNGdr;
};

Partition partition(const Model& m, const Linearisation& lin) {
  Partition p;
  const int nd = p.nd = m.nd(), nr = p.nr = m.nr();
  const Eigen::MatrixXd KNG = lin.K + lin.N + lin.G, CD = lin.C + lin.D;
  p.Mdd = lin.M.topLeftCorner(nd, nd);
  p.Mdr = lin.M.topRightCorner(nd, nr), p.CDdr = CD.topRightCorner(nd, nr),
  p.KNGdr = KNG.topRightCorner(nd, nr);
  p.CDdd = CD.topLeftCorner(nd, nd), p.KNGdd = KNG.topLeftCorner(nd, nd);
  return p;
}

// The state coordinates: q_d = R p + H g, p the dynamic coordinates P (R_P = I) that carry the
// massive directions, H g the static response of the massless ones (the header says how). Without
// massless directions R = I, H = 0 and P = every dynamic coordinate: what follows is then the
// plain A21 = -Mdd^-1 Kdd of doc/design.md §3.
struct StateCoordinates {
  model::MasslessCondensation mc;
  int nb = 0, na = 0;  // massless directions, state coordinates
  std::vector<int> P;
  Eigen::MatrixXd R, H;
  Eigen::LDLT<Eigen::MatrixXd> mass;  // of R^T Mdd R, the mass the state coordinates carry
};

// Z (the null space of Mdd) and T (the massive directions' static shape), as model errors.
model::MasslessCondensation massless_directions(const Model& m, const Partition& p) {
  if (p.nd == 0) return {};
  const std::vector<std::string> labels(m.generalised.begin(), m.generalised.begin() + p.nd);
  try {
    return model::condense_massless(p.Mdd, p.KNGdd, p.CDdd, {}, {}, labels);
  } catch (const std::invalid_argument& e) {
    throw common::InputError(
        m.file, std::string("the mass matrix of the dynamic coordinates: ") + e.what());
  }
}

// P, R = T T_P^-1 and H = Z (Z^T Kdd Z)^-1 Z^T when there are massless directions. P: a pivoted
// QR of T^T with the columns weighted by sqrt(Mdd_ii) (unit-free: sqrt(kg) times the coordinate's
// unit) picks n_a coordinates that carry mass and whose rows of T are well conditioned.
void pick_state_coordinates(const Model& m, const Partition& p, StateCoordinates& s) {
  const int na = s.na;
  const Eigen::VectorXd w = p.Mdd.diagonal().cwiseMax(0.0).cwiseSqrt();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(s.mc.T.transpose() * w.asDiagonal());
  for (int j = 0; j < na; ++j) s.P[static_cast<std::size_t>(j)] = qr.colsPermutation().indices()(j);
  std::sort(s.P.begin(), s.P.end());
  Eigen::MatrixXd TP(na, na);
  for (int j = 0; j < na; ++j) TP.row(j) = s.mc.T.row(s.P[static_cast<std::size_t>(j)]);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(TP.transpose());
  if (!(lu.rcond() > 1e-12))
    throw common::InputError(m.file,
                             "massless condensation: no set of dynamic coordinates describes "
                             "the massive directions (rows of T singular)");
  s.R = lu.solve(s.mc.T.transpose()).transpose();
  for (int j = 0; j < na; ++j)
    s.R.row(s.P[static_cast<std::size_t>(j)]) = Eigen::RowVectorXd::Unit(na, j);
  const Eigen::MatrixXd Kbb = s.mc.Z.transpose() * p.KNGdd * s.mc.Z;
  s.H = s.mc.Z * Kbb.partialPivLu().solve(s.mc.Z.transpose());
}

StateCoordinates state_coordinates(const Model& m, const Partition& p) {
  StateCoordinates s;
  s.mc = massless_directions(m, p);
  const int nd = p.nd, nb = s.nb = s.mc.massless_count, na = s.na = nd - nb;
  s.P.resize(static_cast<std::size_t>(na));
  s.R = Eigen::MatrixXd::Identity(nd, na), s.H = Eigen::MatrixXd::Zero(nd, nd);
  if (nb == 0) {
    for (int j = 0; j < na; ++j) s.P[static_cast<std::size_t>(j)] = j;
  } else {
    pick_state_coordinates(m, p, s);
  }
  const Eigen::MatrixXd Mr = s.R.transpose() * p.Mdd * s.R;
  s.mass.compute(Mr);
  if (na > 0 && (s.mass.info() != Eigen::Success || !s.mass.isPositive()))
    throw common::InputError(m.file,
                             "the mass matrix of the dynamic coordinates is not positive definite");
  return s;
}

// Selecting the inputs: the columns of u. A force or an actuator stress enters g through
//   B_f = DF(x)^T (force:) or -DF(e)^T (stress:);
// a prescribed coordinate enters as its position, velocity or acceleration (pos:, vel:, acc:).
struct InputSelection {
  std::vector<int> pos_in, vel_in, acc_in;  // per prescribed coordinate: its input column, or -1
  std::vector<int> stress_in;               // per deformation: its actuator stress's column, or -1
  Eigen::MatrixXd Bf;                       // generalised forces of the force and stress inputs
};

void select_prescribed_input(const Model& m, const std::string& kind, const std::string& target,
                             const std::string& place, int j, InputSelection& in) {
  const int nd = m.nd();
  const int i = generalised_index(m, target);
  if (i < nd)
    throw common::InputError(place, "'" + target +
                                        "' is not a prescribed coordinate (prescribed: list it in "
                                        "[coordinates] prescribed)");
  auto& slot = kind == "pos" ? in.pos_in : kind == "vel" ? in.vel_in : in.acc_in;
  if (slot[i - nd] >= 0) throw common::InputError(place, "listed twice");
  slot[i - nd] = j;
}

InputSelection select_inputs(const Model& m, const Linearisation& lin,
                             const std::vector<std::string>& inputs) {
  const int nd = m.nd(), nr = m.nr(), nu = static_cast<int>(inputs.size());
  InputSelection in{std::vector<int>(nr, -1), std::vector<int>(nr, -1), std::vector<int>(nr, -1),
                    std::vector<int>(m.ne(), -1), Eigen::MatrixXd::Zero(nd, nu)};
  for (int j = 0; j < nu; ++j) {
    const auto [kind, target] = split(inputs[j], "input");
    const std::string place = "input '" + inputs[j] + "'";
    if (kind == "force") {
      const int i = m.coordinate_index(target);
      if (i < 0) throw common::InputError(place, "unknown nodal coordinate '" + target + "'");
      in.Bf.col(j) = lin.DFx.row(i).head(nd).transpose();
    } else if (kind == "stress") {
      const int k = m.deformation_index(target);
      if (k < 0) throw common::InputError(place, "unknown deformation '" + target + "'");
      if (is_rigid(m, k))
        throw common::InputError(
            place, "'" + target +
                       "' is rigid: an actuator stress needs a flexible or released deformation");
      in.Bf.col(j) = -lin.DFe.row(k).head(nd).transpose();
      in.stress_in[k] = j;
    } else if (kind == "pos" || kind == "vel" || kind == "acc") {
      select_prescribed_input(m, kind, target, place, j, in);
    } else {
      throw common::InputError(place,
                               "unknown input kind '" + kind + "' (force, stress, pos, vel, acc)");
    }
  }
  return in;
}

// Selecting the outputs: which prescribed coordinates' positions and velocities the outputs
// depend on (x' = DF(x) q' + V q, x'' = DF(x) q'' + Z q' + W q; sigma = S e + Sd e'), for the
// integrator states. The names are checked here for their form, in output_equation for the rest.
struct OutputNeeds {
  std::vector<bool> pos, vel;  // per prescribed coordinate
};

OutputNeeds select_outputs(const Model& m, const Linearisation& lin,
                           const std::vector<std::string>& outputs) {
  const int nd = m.nd(), nr = m.nr();
  OutputNeeds need{std::vector<bool>(nr, false), std::vector<bool>(nr, false)};
  for (const auto& name : outputs) {
    const auto [kind, target] = split(name, "output");
    for (int r = 0; r < nr; ++r) {
      const int c = nd + r;
      if (const int i = m.coordinate_index(target); i >= 0) {
        if (kind == "pos") need.pos[r] = need.pos[r] || lin.DFx(i, c) != 0.0;
        if (kind == "vel") {
          need.vel[r] = need.vel[r] || lin.DFx(i, c) != 0.0;
          need.pos[r] = need.pos[r] || lin.Vx(i, c) != 0.0;
        }
        if (kind == "acc") {
          need.vel[r] = need.vel[r] || lin.Zx(i, c) != 0.0;
          need.pos[r] = need.pos[r] || lin.Wx(i, c) != 0.0;
        }
      } else if (const int k = m.deformation_index(target); k >= 0) {
        const Eigen::RowVectorXd de = lin.DFe.row(k);
        if (kind == "pos") need.pos[r] = need.pos[r] || de(c) != 0.0;
        if (kind == "stress") {
          need.pos[r] = need.pos[r] || (lin.S.row(k) * lin.DFe.col(c))(0) != 0.0 ||
                        (lin.Sd.row(k) * lin.Ved.col(c))(0) != 0.0;
          need.vel[r] = need.vel[r] || (lin.Sd.row(k) * lin.DFe.col(c))(0) != 0.0;
        }
      }
    }
  }
  return need;
}

// The state vector z = (p, p', integrator states): a prescribed coordinate given by a higher
// derivative only gets the integrator states (qr, qr') that the dynamics (KNGdr, CDdr != 0) or the
// outputs need; one the dynamics need the acceleration of (Mdr != 0) must be given as acc:.
struct States {
  std::vector<std::string> names;
  std::vector<int> pos_state, vel_state;  // per prescribed coordinate: its state, or -1
};

States choose_states(const Model& m, const Partition& p, const std::vector<int>& P,
                     const InputSelection& in, const OutputNeeds& need) {
  States st{{}, std::vector<int>(p.nr, -1), std::vector<int>(p.nr, -1)};
  for (const int i : P) st.names.push_back("pos:" + m.generalised[i]);
  for (const int i : P) st.names.push_back("vel:" + m.generalised[i]);
  for (int r = 0; r < p.nr; ++r) {
    const std::string& label = m.generalised[p.nd + r];
    const bool need_pos = nonzero_col(p.KNGdr, r) || need.pos[r];
    const bool need_vel = nonzero_col(p.CDdr, r) || need.vel[r] || (need_pos && in.pos_in[r] < 0);
    const bool need_acc = nonzero_col(p.Mdr, r) || (need_vel && in.vel_in[r] < 0);
    const bool any = in.pos_in[r] >= 0 || in.vel_in[r] >= 0 || in.acc_in[r] >= 0;
    if (!any) continue;  // held at its operating value
    if (need_acc && in.acc_in[r] < 0)
      throw common::InputError("input 'pos:" + label + "'/'vel:" + label + "'",
                               "the dynamics depend on the acceleration of '" + label +
                                   "': give it as acc:" + label + " (or all of acc, vel and pos)");
    if (need_vel && in.vel_in[r] < 0)
      st.vel_state[r] = static_cast<int>(st.names.size()), st.names.push_back("vel:" + label);
    if (need_pos && in.pos_in[r] < 0)
      st.pos_state[r] = static_cast<int>(st.names.size()), st.names.push_back("pos:" + label);
  }
  return st;
}

// The prescribed coordinates as signals: qr from pos: or its integrator state, qr' from vel: or
// its integrator state, qr'' from acc: (zero when none is given: held at the operating value).
struct PrescribedSignals {
  std::vector<Signal> pos, vel, acc;
};

PrescribedSignals prescribed_signals(int nr, int nz, int nu, const InputSelection& in,
                                     const States& st) {
  PrescribedSignals r{std::vector<Signal>(nr), std::vector<Signal>(nr), std::vector<Signal>(nr)};
  for (int k = 0; k < nr; ++k) {
    r.pos[k] = {unit(nz, st.pos_state[k]), unit(nu, in.pos_in[k])};
    r.vel[k] = {unit(nz, st.vel_state[k]), unit(nu, in.vel_in[k])};
    r.acc[k] = {Eigen::RowVectorXd::Zero(nz), unit(nu, in.acc_in[k])};
  }
  return r;
}

// The generalised force of inputs and prescribed coordinates on the dynamic rows,
//   g = Bf u - Mdr qr'' - CDdr qr' - KNGdr qr,
// and, for the massless part H g (Z^T Mdr = 0: M is positive semi-definite), its static part and
// the rates that exist as signals: g' without Bf u', g'' without Bf u'' and CDdr qr'''.
struct GeneralisedForce {
  Signals g, g_static, g_rate, g_rate2;
};

GeneralisedForce generalised_force(const Partition& p, const PrescribedSignals& r,
                                   const Eigen::MatrixXd& Bf, int nb, int nz) {
  const int nd = p.nd, nu = static_cast<int>(Bf.cols());
  const Eigen::MatrixXd& Mdr = p.Mdr;
  const Eigen::MatrixXd& CDdr = p.CDdr;
  const Eigen::MatrixXd& KNGdr = p.KNGdr;
  GeneralisedForce f{{Eigen::MatrixXd::Zero(nd, nz), Bf},
                     {Eigen::MatrixXd::Zero(nd, nz), Bf},
                     {Eigen::MatrixXd::Zero(nd, nz), Eigen::MatrixXd::Zero(nd, nu)},
                     {Eigen::MatrixXd::Zero(nd, nz), Eigen::MatrixXd::Zero(nd, nu)}};
  for (int k = 0; k < p.nr; ++k) {
    f.g.z -= Mdr.col(k) * r.acc[k].cz + CDdr.col(k) * r.vel[k].cz + KNGdr.col(k) * r.pos[k].cz;
    f.g.u -= Mdr.col(k) * r.acc[k].du + CDdr.col(k) * r.vel[k].du + KNGdr.col(k) * r.pos[k].du;
    if (nb == 0) continue;
    f.g_static.z -= CDdr.col(k) * r.vel[k].cz + KNGdr.col(k) * r.pos[k].cz;
    f.g_static.u -= CDdr.col(k) * r.vel[k].du + KNGdr.col(k) * r.pos[k].du;
    f.g_rate.z -= CDdr.col(k) * r.acc[k].cz + KNGdr.col(k) * r.vel[k].cz;
    f.g_rate.u -= CDdr.col(k) * r.acc[k].du + KNGdr.col(k) * r.vel[k].du;
    f.g_rate2.z -= KNGdr.col(k) * r.acc[k].cz;
    f.g_rate2.u -= KNGdr.col(k) * r.acc[k].du;
  }
  return f;
}

// The dynamic coordinates and their rates as signals (q = R p + H g, q' = R p' + H g',
// q'' = R p'' + H g''), and p'' from the state equations.
struct DynamicSignals {
  std::array<Signals, 3> q;  // q_d, q_d', q_d''
  Signals p_acc;             // p''
};

// The state equations: the rows R^T of the dynamics,
//   R^T Mdd R p'' = R^T (g - CDdd q' - KNGdd q),
// solved for p'' (A21 = -Mdd^-1 KNGdd, A22 = -Mdd^-1 CDdd and B2 without massless directions).
DynamicSignals state_equations(const Partition& p, const StateCoordinates& s,
                               const GeneralisedForce& f, int nz, int nu) {
  const int nd = p.nd, na = s.na;
  const Eigen::MatrixXd& R = s.R;
  const Eigen::MatrixXd& H = s.H;
  DynamicSignals d;
  auto& [q0, q1, q2] = d.q;
  q0 = {Eigen::MatrixXd::Zero(nd, nz), Eigen::MatrixXd::Zero(nd, nu)};
  q1 = {Eigen::MatrixXd::Zero(nd, nz), Eigen::MatrixXd::Zero(nd, nu)};
  q0.z.leftCols(na) = R;
  q1.z.middleCols(na, na) = R;
  if (s.nb > 0) {
    q0.z += H * f.g_static.z, q0.u += H * f.g_static.u;
    q1.z += H * f.g_rate.z, q1.u += H * f.g_rate.u;
  }
  d.p_acc.z = solve_or_empty(s.mass, R.transpose() * (f.g.z - p.CDdd * q1.z - p.KNGdd * q0.z));
  d.p_acc.u = solve_or_empty(s.mass, R.transpose() * (f.g.u - p.CDdd * q1.u - p.KNGdd * q0.u));
  q2 = {R * d.p_acc.z, R * d.p_acc.u};
  if (s.nb > 0) q2.z += H * f.g_rate2.z, q2.u += H * f.g_rate2.u;
  return d;
}

// A and B: p' = p' (the identity block), p'' from the state equations, and each integrator
// state's rate the prescribed signal one derivative up (qr' from vel:, qr'' from acc:).
void state_matrices(StateSpace& ss, int na, const DynamicSignals& d, const PrescribedSignals& r,
                    const States& st) {
  const int nz = static_cast<int>(st.names.size()), nu = static_cast<int>(d.p_acc.u.cols());
  ss.A = Eigen::MatrixXd::Zero(nz, nz);
  ss.B = Eigen::MatrixXd::Zero(nz, nu);
  ss.A.block(0, na, na, na).setIdentity();
  ss.A.middleRows(na, na) = d.p_acc.z;
  ss.B.middleRows(na, na) = d.p_acc.u;
  for (std::size_t k = 0; k < r.pos.size(); ++k) {
    if (st.pos_state[k] >= 0)
      ss.A.row(st.pos_state[k]) = r.vel[k].cz, ss.B.row(st.pos_state[k]) = r.vel[k].du;
    if (st.vel_state[k] >= 0)
      ss.A.row(st.vel_state[k]) = r.acc[k].cz, ss.B.row(st.vel_state[k]) = r.acc[k].du;
  }
}

// What the condensation did, and the inputs whose rates the massless part would need but no
// signal carries (a column of Bf, KNGdr or CDdr with a component along Z: Z^T col != 0).
Condensation condensation_report(const Model& m, const std::vector<std::string>& inputs,
                                 const Partition& p, const StateCoordinates& s,
                                 const InputSelection& in, const States& st) {
  Condensation c;
  c.massless_count = s.nb;
  if (s.nb == 0) return c;
  std::vector<bool> is_state(static_cast<std::size_t>(p.nd), false);
  for (const int i : s.P) {
    is_state[static_cast<std::size_t>(i)] = true;
    c.state_coordinates.push_back(m.generalised[i]);
  }
  for (int i = 0; i < p.nd; ++i)
    if (!is_state[static_cast<std::size_t>(i)]) c.condensed.push_back(m.generalised[i]);
  c.damping_coupling = s.mc.damping_coupling;
  auto couples = [&](const Eigen::VectorXd& col) {
    const double n = col.norm();
    return n > 0.0 && (s.mc.Z.transpose() * col).norm() > 1e-9 * n;
  };
  auto drop = [&](int j) {
    if (j >= 0 && std::find(c.rate_terms_dropped.begin(), c.rate_terms_dropped.end(), inputs[j]) ==
                      c.rate_terms_dropped.end())
      c.rate_terms_dropped.push_back(inputs[j]);
  };
  for (int j = 0; j < static_cast<int>(inputs.size()); ++j)
    if (couples(in.Bf.col(j))) drop(j);
  for (int r = 0; r < p.nr; ++r) {
    const bool has_vel = in.vel_in[r] >= 0 || st.vel_state[r] >= 0, has_acc = in.acc_in[r] >= 0;
    const bool k_couples = couples(p.KNGdr.col(r)), c_couples = couples(p.CDdr.col(r));
    if ((k_couples && (!has_vel || !has_acc)) || c_couples) {
      drop(in.pos_in[r]);
      drop(in.vel_in[r]);
      drop(in.acc_in[r]);
    }
  }
  return c;
}

// One output as the combination it is of the generalised coordinates' signals and the inputs,
//   y = sum_t w_t . q^(k_t) + sum_j e_j u_j,
// the terms summed in their order; e: the inputs that reach y other than through q.
struct OutputEquation {
  std::vector<std::pair<int, Eigen::RowVectorXd>> terms;  // (derivative order k, w over all q)
  std::vector<std::pair<int, double>> direct;             // (input column j, e_j)
};

// A support force by virtual work: release the coordinate into a prescribed one held at its value;
// its generalised force is the support force (a rigid deformation's stress is minus it, since
// d e_k / d q_k = 1): the released equation's row, M q'' + CD q' + KNG q minus the forces applied.
OutputEquation reaction_equation(const Model& m, const Linearisation& lin,
                                 const std::vector<std::string>& inputs, const std::string& kind,
                                 const std::string& target) {
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
  OutputEquation eq;
  eq.terms.emplace_back(2, sign * rl.M.row(ia).head(m.nq()));
  eq.terms.emplace_back(1, sign * (rl.C + rl.D).row(ia).head(m.nq()));
  eq.terms.emplace_back(0, sign * (rl.K + rl.N + rl.G).row(ia).head(m.nq()));
  for (int j = 0; j < static_cast<int>(inputs.size()); ++j) {
    const auto [in_kind, in_target] = split(inputs[j], "input");
    if (in_kind == "force")
      eq.direct.emplace_back(j, -(sign * rl.DFx(m.coordinate_index(in_target), ia)));
    if (in_kind == "stress")
      eq.direct.emplace_back(j, sign * rl.DFe(m.deformation_index(in_target), ia));
  }
  return eq;
}

// The index in q of a superelement's modal amplitude "eta<k>.<id>", or -1.
int modal_coordinate_index(const Model& m, const std::string& label) {
  for (const auto& body : m.superelements)
    if (std::find(body.mode_labels.begin(), body.mode_labels.end(), label) !=
        body.mode_labels.end())
      return static_cast<int>(std::find(m.generalised.begin(), m.generalised.end(), label) -
                              m.generalised.begin());
  return -1;
}

// The output equation of one name: x = DF(x) q, x' = DF(x) q' + V q, x'' = DF(x) q'' + Z q' + W q
// of a nodal coordinate; e = DF(e) q of a deformation; sigma = sigma_a + S e + Sd e' of a flexible
// one (its own actuator stress the feedthrough); a reaction, or a rigid deformation's stress, by
// reaction_equation.
OutputEquation output_equation(const Model& m, const Linearisation& lin,
                               const std::vector<std::string>& inputs,
                               const std::vector<int>& stress_in, const std::string& name) {
  const auto [kind, target] = split(name, "output");
  const std::string place = "output '" + name + "'";
  const int i = m.coordinate_index(target);
  const int k = m.deformation_index(target);
  OutputEquation eq;
  if (i >= 0 && (kind == "pos" || kind == "vel" || kind == "acc")) {
    if (kind == "pos") eq.terms = {{0, lin.DFx.row(i)}};
    if (kind == "vel") eq.terms = {{1, lin.DFx.row(i)}, {0, lin.Vx.row(i)}};
    if (kind == "acc") eq.terms = {{2, lin.DFx.row(i)}, {1, lin.Zx.row(i)}, {0, lin.Wx.row(i)}};
  } else if (k >= 0 && kind == "pos") {
    eq.terms = {{0, lin.DFe.row(k)}};
  } else if ((i >= 0 && kind == "reaction") || (k >= 0 && kind == "stress" && is_rigid(m, k))) {
    return reaction_equation(m, lin, inputs, kind, target);
  } else if (k >= 0 && kind == "stress") {
    eq.terms = {{0, lin.S.row(k) * lin.DFe + lin.Sd.row(k) * lin.Ved},
                {1, lin.Sd.row(k) * lin.DFe}};
    if (stress_in[k] >= 0) eq.direct = {{stress_in[k], 1.0}};
  } else if (const int g = modal_coordinate_index(m, target);
             g >= 0 && (kind == "pos" || kind == "vel" || kind == "acc")) {
    // A superelement's modal amplitude is its own generalised coordinate: eta, eta', eta''.
    eq.terms = {{kind == "pos" ? 0 : kind == "vel" ? 1 : 2, Eigen::RowVectorXd::Unit(m.nq(), g)}};
  } else if (i < 0 && k < 0) {
    throw common::InputError(place, "unknown coordinate or deformation '" + target + "'");
  } else {
    throw common::InputError(
        place, "unknown output kind '" + kind +
                   "' for this target (pos/vel/acc/reaction of a nodal coordinate, pos/stress of "
                   "a deformation)");
  }
  return eq;
}

// Generalised coordinate i's signal of a derivative order: q (0), q' (1), q'' (2).
Signal coordinate_signal(const DynamicSignals& d, const PrescribedSignals& r, int order, int i) {
  const int nd = static_cast<int>(d.q[0].z.rows());
  if (i < nd) {
    const Signals& q = d.q[static_cast<std::size_t>(order)];
    return {q.z.row(i), q.u.row(i)};
  }
  const int k = i - nd;
  return order == 0 ? r.pos[k] : order == 1 ? r.vel[k] : r.acc[k];
}

// The output equation's rows of C and D: y = C z + D u with
//   C = sum_t w_t . Q_(k_t),z,   D = sum_t w_t . Q_(k_t),u + e   (the feedthrough),
// Q_k,z and Q_k,u the state and input parts of the coordinates' signals q^(k).
Signal output_rows(const OutputEquation& eq, const DynamicSignals& d, const PrescribedSignals& r,
                   int nz, int nu) {
  Signal s{Eigen::RowVectorXd::Zero(nz), Eigen::RowVectorXd::Zero(nu)};
  for (const auto& [order, w] : eq.terms)
    for (int i = 0; i < static_cast<int>(w.size()); ++i) {
      if (w(i) == 0.0) continue;
      const Signal qi = coordinate_signal(d, r, order, i);
      s.cz += w(i) * qi.cz;
      s.du += w(i) * qi.du;
    }
  for (const auto& [j, e] : eq.direct) s.du(j) += e;
  return s;
}

}  // namespace

StateSpace build_state_space(const Model& m, const Linearisation& lin,
                             const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs, Condensation* condensation) {
  const int nu = static_cast<int>(inputs.size());
  const Partition p = partition(m, lin);
  const StateCoordinates s = state_coordinates(m, p);
  const InputSelection in = select_inputs(m, lin, inputs);
  const States st = choose_states(m, p, s.P, in, select_outputs(m, lin, outputs));
  const int nz = static_cast<int>(st.names.size());
  const PrescribedSignals r = prescribed_signals(p.nr, nz, nu, in, st);
  const DynamicSignals d = state_equations(p, s, generalised_force(p, r, in.Bf, s.nb, nz), nz, nu);
  if (condensation) *condensation = condensation_report(m, inputs, p, s, in, st);

  StateSpace ss;
  ss.states = st.names;
  ss.inputs = inputs;
  ss.outputs = outputs;
  state_matrices(ss, s.na, d, r, st);
  ss.C = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(outputs.size()), nz);
  ss.D = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(outputs.size()), nu);
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const Signal y =
        output_rows(output_equation(m, lin, inputs, in.stress_in, outputs[o]), d, r, nz, nu);
    ss.C.row(static_cast<Eigen::Index>(o)) = y.cz;
    ss.D.row(static_cast<Eigen::Index>(o)) = y.du;
  }
  ss.validate();
  return ss;
}

}  // namespace flexloop::plant::lti
